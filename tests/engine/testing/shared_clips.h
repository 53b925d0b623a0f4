// Every clip of the real test data (../shared/data): CMU 01_01 and the BVH
// and glTF files beside it, parsed by our readers. Empty when the data is
// absent (a user's clone); for tests and benchmarks alike.
#pragma once

#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "armature/engine/anim/clip.h"
#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/gltf/gltf.h"
#include "test_files.h"

namespace armature::test_util {

struct SharedClip {
  std::string name;  // "bvh/cmu_01_01.bvh", "gltf/RobotExpressive/RobotExpressive.glb#Walking"
  std::shared_ptr<const Clip> clip;
};

#ifdef ARMATURE_SHARED_DATA
inline std::vector<SharedClip> LoadSharedClips() {
  namespace fs = std::filesystem;
  std::vector<SharedClip> clips;
  const fs::path root = SharedData("");
  if (!fs::is_directory(root)) return clips;
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& path : files) {
    const std::string ext = path.extension().string(), name = fs::relative(path, root).string();
    const std::optional<std::string> bytes = ReadFileBytes(path);
    if (!bytes) continue;
    if (ext == ".bvh") {
      StatusOr<BvhData> bvh = ParseBvh(*bytes);
      if (bvh.ok()) clips.push_back({name, bvh->clip});
    } else if (ext == ".gltf" || ext == ".glb") {
      ResourceMap resources;  // external buffers beside the file
      for (const fs::directory_entry& e : fs::directory_iterator(path.parent_path()))
        if (e.path().extension() == ".bin")
          if (std::optional<std::string> bin = ReadFileBytes(e.path())) resources[e.path().filename().string()] = *bin;
      StatusOr<AssetContents> asset = ParseGltf(*bytes, ext == ".glb", path.stem().string(), resources);
      if (!asset.ok()) continue;
      for (const NamedClip& c : asset->clips)
        if (c.clip && c.clip->skeleton && c.clip->skeleton->size() > 0) clips.push_back({name + "#" + c.name, c.clip});
    }
  }
  return clips;
}

// CMU 01_01 (parsed once), or null when the data is absent.
inline std::shared_ptr<const Clip> SharedCmuClip() {
  static const std::vector<SharedClip> clips = LoadSharedClips();
  for (const SharedClip& c : clips)
    if (c.name == "bvh/cmu_01_01.bvh") return c.clip;
  return nullptr;
}
#endif

}  // namespace armature::test_util
