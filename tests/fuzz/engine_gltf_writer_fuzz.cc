// glTF read → BVH write → read: the engine has no glTF writer; a glTF clip
// leaves the server as BVH (ExportClip), so every imported clip must export
// and read back.
#include <cstdint>
#include <string_view>

#include "armature/engine/io/gltf.h"
#include "round_trip.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace armature;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  auto contents = ParseGltf(bytes, bytes.substr(0, 4) == "glTF", "f", {}, fuzz::Limits());
  if (!contents.ok()) return 0;
  for (const auto& c : contents->clips) fuzz::ExpectBvhRoundTrip(*c.clip);
  return 0;
}
