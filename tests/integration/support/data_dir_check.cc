#include "support/data_dir_check.h"

#include <cstdint>
#include <cstring>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "support/server_process.h"

namespace armature::testing {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json Manifest(const fs::path& data_dir) {
  if (!fs::exists(data_dir / "manifest.json")) return json{{"assets", json::array()}};
  return json::parse(ReadFile(data_dir / "manifest.json"));
}

uint32_t U32(const std::string& s, size_t at) {
  uint32_t v = 0;
  std::memcpy(&v, s.data() + at, 4);  // glb is little-endian, like every machine this runs on
  return v;
}

}  // namespace

std::set<std::string> ManifestAssetNames(const fs::path& data_dir) {
  std::set<std::string> names;
  const json manifest = Manifest(data_dir);  // named: a range-for over a temporary's member dangles
  for (const json& entry : manifest["assets"]) names.insert(entry["name"].get<std::string>());
  return names;
}

std::vector<std::string> LeftoverFiles(const fs::path& data_dir) {
  std::set<fs::path> named;
  const json manifest = Manifest(data_dir);
  for (const json& entry : manifest["assets"]) {
    named.insert(data_dir / entry["file"].get<std::string>());
    if (entry.contains("resources"))
      for (const auto& [uri, file] : entry["resources"].items()) named.insert(data_dir / file.get<std::string>());
  }
  std::vector<std::string> leftovers;
  for (const auto& e : fs::recursive_directory_iterator(data_dir)) {
    if (!e.is_regular_file()) continue;
    const std::string name = e.path().filename().string();
    const bool in_files = e.path().parent_path() == data_dir / "files";
    const bool expected =
        in_files ? named.contains(e.path()) : (name == "manifest.json" || name == ".lock" || name == ".space-reserve");
    if (!expected || name.find(".tmp-") != std::string::npos) leftovers.push_back(e.path().string());
  }
  return leftovers;
}

SplitGltf SplitGlb(const std::string& glb, const std::string& bin_uri) {
  if (glb.size() < 20 || glb.compare(0, 4, "glTF") != 0) throw std::runtime_error("not a glb");
  const uint32_t json_length = U32(glb, 12);
  json doc = json::parse(glb.substr(20, json_length));
  const size_t bin_at = 20 + json_length;
  const uint32_t bin_length = U32(glb, bin_at);
  doc["buffers"][0]["uri"] = bin_uri;
  return {doc.dump(), glb.substr(bin_at + 8, bin_length)};
}

}  // namespace armature::testing
