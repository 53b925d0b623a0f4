// glTF read → BVH write → read, and glTF read → glTF write (with the file's
// skinned meshes; .glb and .gltf alternately) → read: a glTF clip leaves the
// server through ExportClip in either format, so every imported clip must
// export and read back.
#include <cstdint>
#include <string_view>

#include "armature/engine/io/gltf/gltf.h"
#include "round_trip.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace armature;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  auto contents = ParseGltf(bytes, bytes.substr(0, 4) == "glTF", "f", {}, fuzz::Limits());
  if (!contents.ok()) return 0;
  for (const auto& c : contents->clips) {
    fuzz::ExpectBvhRoundTrip(*c.clip);
    fuzz::ExpectGltfRoundTrip(*c.clip, *contents, size % 2 == 0);
  }
  return 0;
}
