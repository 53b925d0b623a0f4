// OBJ reader: any bytes give a finalized mesh or a Status.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "armature/engine/io/obj/obj.h"
#include "armature/base/utf8.h"
#include "fuzz_limits.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace armature;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> warnings;
  auto mesh = ParseObj(text, "f", &warnings, fuzz::Limits());
  if (!mesh.ok() && !IsValidUtf8(mesh.status().message())) std::abort();
  for (const std::string& w : warnings)
    if (!IsValidUtf8(w)) std::abort();
  return 0;
}
