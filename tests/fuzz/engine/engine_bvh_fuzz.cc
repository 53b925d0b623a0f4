// BVH reader: any bytes give a BvhData or a Status; an accepted file is a
// valid skeleton and clip.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "armature/engine/io/bvh/bvh.h"
#include "armature/base/utf8.h"
#include "fuzz_limits.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace armature;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto bvh = ParseBvh(text, fuzz::Limits());
  if (!bvh.ok()) {
    if (!IsValidUtf8(bvh.status().message())) std::abort();
    return 0;
  }
  if (!bvh->skeleton->Validate().ok() || !bvh->clip->Validate().ok()) std::abort();
  for (const std::string& name : bvh->skeleton->names)
    if (!IsValidUtf8(name)) std::abort();
  return 0;
}
