// What a data dir holds, as the tests check it: the manifest's assets, and
// the files that no manifest entry names (leftovers of a failed write).
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace armature::testing {

// The asset names the manifest lists (empty when there is none).
std::set<std::string> ManifestAssetNames(const std::filesystem::path& data_dir);

// Files in the data dir that should not be there: temporary files anywhere,
// and files in files/ that no manifest entry names. The lock file, the
// manifest and the delete reserve are expected.
std::vector<std::string> LeftoverFiles(const std::filesystem::path& data_dir);

// A .glb split into a .gltf (its buffer 0 given `bin_uri`) and that buffer.
struct SplitGltf {
  std::string gltf;
  std::string bin;
};
SplitGltf SplitGlb(const std::string& glb, const std::string& bin_uri);

}  // namespace armature::testing
