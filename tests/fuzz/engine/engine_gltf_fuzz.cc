// glTF importer: .glb when the bytes start with the GLB magic, else .gltf
// JSON. Any bytes give contents or a Status with a UTF-8 message.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "armature/engine/io/gltf/gltf.h"
#include "armature/engine/mesh/mesh.h"
#include "armature/base/utf8.h"
#include "fuzz_limits.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace armature;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const bool binary = bytes.substr(0, 4) == "glTF";
  auto contents = ParseGltf(bytes, binary, "f", {}, fuzz::Limits());
  if (!contents.ok()) {
    if (!IsValidUtf8(contents.status().message())) std::abort();
    return 0;
  }
  for (const auto& c : contents->clips)
    if (!c.clip->Validate().ok() || !IsValidUtf8(c.name)) std::abort();
  for (const auto& s : contents->skeletons)
    for (const std::string& name : s.skeleton->names)
      if (!IsValidUtf8(name)) std::abort();
  for (const auto& m : contents->meshes)
    if (!IsValidUtf8(m.name)) std::abort();
  return 0;
}
