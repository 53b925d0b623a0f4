#include "server/assets/asset_record_json.h"

#include "server/assets/asset_store.h"

namespace armature::server {
using json = nlohmann::json;

json RecordToJson(const AssetRecord& r) {
  json j = {{"name", r.name}, {"format", FormatName(r.format)}, {"filename", r.filename},
            {"file", r.file}, {"size_bytes", r.size_bytes},     {"imported_at", r.imported_at}};
  if (!r.resources.empty()) j["resources"] = r.resources;
  if (!r.animates.empty()) j["animates"] = r.animates;
  if (!r.precision.empty()) j["precision"] = r.precision;
  if (!r.version.empty()) j["version"] = r.version;
  return j;
}

StatusOr<AssetRecord> RecordFromJson(const json& j) {
  AssetRecord r;
  try {
    r.name = j.at("name").get<std::string>();
    ARMATURE_ASSIGN_OR_RETURN(auto format, DetectFormat(j.at("format").get<std::string>(), "", ""));
    r.format = format;
    r.filename = j.value("filename", "");
    r.file = j.at("file").get<std::string>();
    r.size_bytes = j.value("size_bytes", int64_t{0});
    r.imported_at = j.value("imported_at", "");
    if (j.contains("resources")) r.resources = j.at("resources").get<std::map<std::string, std::string>>();
    r.animates = j.value("animates", "");
    r.precision = j.value("precision", "");
    r.version = j.value("version", "");
  } catch (const json::exception& e) {
    return Status::InvalidArgument(std::string("manifest entry: ") + e.what());
  }
  return r;
}

// A manifest path of a stored file: "files/<one safe name>", never outside the data dir.
bool IsStoredFilePath(std::string_view path) {
  constexpr std::string_view kPrefix = "files/";
  if (!path.starts_with(kPrefix)) return false;
  const std::string_view name = path.substr(kPrefix.size());
  return !name.empty() && name.front() != '.' && name.find('/') == std::string_view::npos &&
         name.find('\\') == std::string_view::npos && name.find('\0') == std::string_view::npos;
}

Status CheckRecordPaths(const AssetRecord& r) {
  if (!IsStoredFilePath(r.file))
    return Status::InvalidArgument("manifest entry '" + r.name + "': bad file path '" + r.file + "'");
  for (const auto& [uri, file] : r.resources)
    if (!IsStoredFilePath(file))
      return Status::InvalidArgument("manifest entry '" + r.name + "': bad resource path '" + file + "'");
  return ValidateAssetName(r.name).WithContext("manifest entry: ");
}

}  // namespace armature::server
