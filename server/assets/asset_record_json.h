// An AssetRecord as JSON: a local manifest's entry, and the body of a version
// record on a bucket (bucket/bucket_layout.h).
#pragma once

#include <string_view>

#include <nlohmann/json.hpp>

#include "armature/base/status.h"
#include "server/assets/catalog.h"

namespace armature::server {

nlohmann::json RecordToJson(const AssetRecord& r);
// INVALID_ARGUMENT "manifest entry: …" for a missing or mistyped field.
StatusOr<AssetRecord> RecordFromJson(const nlohmann::json& j);

// A manifest path of a stored file: "files/<one safe name>", never outside the data dir.
bool IsStoredFilePath(std::string_view path);
// The record's name is valid and its files are stored file paths.
Status CheckRecordPaths(const AssetRecord& r);

}  // namespace armature::server
