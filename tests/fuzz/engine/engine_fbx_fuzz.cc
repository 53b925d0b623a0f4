// FBX importer (assimp under our checks): any bytes give contents or a
// Status with a UTF-8 message, never a crash, a hang or an escaped exception.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "armature/base/utf8.h"
#include "armature/engine/io/asset.h"
#include "fuzz_limits.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace armature;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  auto contents = ParseAsset(AssetFormat::kFbx, bytes, "f", {}, fuzz::Limits());
  if (!contents.ok()) {
    if (!IsValidUtf8(contents.status().message())) std::abort();
    return 0;
  }
  for (const std::string& w : contents->warnings)
    if (!IsValidUtf8(w)) std::abort();
  for (const auto& s : contents->skeletons)
    if (!s.skeleton->Validate().ok()) std::abort();
  return 0;
}
