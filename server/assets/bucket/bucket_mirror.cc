#include "server/assets/bucket/bucket_mirror.h"

#include <spdlog/spdlog.h>

namespace armature::server {

StatusOr<std::map<std::string, std::vector<std::string>>> BucketMirror::Versions() {
  ARMATURE_ASSIGN_OR_RETURN(auto listing, store_->List(VersionsPrefix(prefix_)));
  return VersionsByName(listing, prefix_);
}

StatusOr<VersionRecord> BucketMirror::ReadRecord(const std::string& name, const std::string& version) {
  ARMATURE_ASSIGN_OR_RETURN(std::string text, store_->Get(VersionKey(prefix_, name, version)));
  auto record = VersionRecordFromJson(text);
  if (!record.ok()) return record.status().WithContext(VersionKey(prefix_, name, version) + ": ");
  if (record->record.name != name || record->record.version != version)
    return Status::InvalidArgument(VersionKey(prefix_, name, version) + ": names another version");
  return record;
}

StatusOr<std::string> BucketMirror::ReadObject(const StoredObject& object) {
  ARMATURE_ASSIGN_OR_RETURN(std::string bytes, store_->Get(object.key));
  if (static_cast<int64_t>(bytes.size()) != object.size || Sha256Hex(bytes) != object.sha256)
    return Status::Internal("object " + object.key + " is corrupt or partial: " + std::to_string(bytes.size()) +
                            " bytes, its record says " + std::to_string(object.size) + " bytes and another SHA-256");
  return bytes;
}

Status BucketMirror::WriteVersion(VersionRecord& version, const std::string& bytes, const ResourceMap& resources) {
  const AssetRecord& r = version.record;
  const std::string source_file = "source" + r.file.substr(r.file.rfind('.'));
  version.source = {ObjectKey(prefix_, r.name, r.version, source_file), static_cast<int64_t>(bytes.size()),
                    Sha256Hex(bytes)};
  std::vector<std::pair<const StoredObject*, const std::string*>> writes = {{&version.source, &bytes}};
  int index = 0;
  for (const auto& [uri, data] : resources) {
    const std::string file = "res" + std::to_string(index++);
    version.resources[uri] = {ObjectKey(prefix_, r.name, r.version, file), static_cast<int64_t>(data.size()),
                              Sha256Hex(data)};
    writes.emplace_back(&version.resources[uri], &data);
  }
  std::vector<std::string> written;
  auto write_all = [&]() -> Status {
    for (const auto& [object, data] : writes) {
      ARMATURE_RETURN_IF_ERROR(store_->Put(object->key, *data));
      written.push_back(object->key);
    }
    return store_->Put(VersionKey(prefix_, r.name, r.version), VersionRecordToJson(version));
  };
  const Status st = write_all();
  if (!st.ok())
    for (const std::string& key : written) (void)store_->Delete(key);
  return st;
}

Status BucketMirror::WriteTombstone(const std::string& name, const std::string& version) {
  VersionRecord tombstone;
  tombstone.deleted = true;
  tombstone.record.name = name;
  tombstone.record.version = version;
  return store_->Put(VersionKey(prefix_, name, version), VersionRecordToJson(tombstone));
}

void BucketMirror::Prune(const std::string& name, int keep) {
  auto listing = store_->List(VersionsPrefix(prefix_) + name + "/");
  if (!listing.ok()) {
    spdlog::warn("could not list the versions of '{}' to prune them: {}", name, listing.status().message());
    return;
  }
  const auto by_name = VersionsByName(*listing, prefix_);
  if (keep <= 0 || !by_name.contains(name) || static_cast<int>(by_name.at(name).size()) <= keep) return;
  const std::vector<std::string>& versions = by_name.at(name);
  for (size_t i = 0; i + keep < versions.size(); ++i) {
    const std::string& version = versions[i];
    if (Status st = store_->Delete(VersionKey(prefix_, name, version)); !st.ok()) {
      spdlog::warn("could not prune version {} of '{}': {}", version, name, st.message());
      return;
    }
    auto objects = store_->List(prefix_ + "objects/" + name + "/" + version + "/");
    if (!objects.ok()) continue;
    for (const ObjectEntry& object : *objects) (void)store_->Delete(object.key);
  }
}

}  // namespace armature::server
