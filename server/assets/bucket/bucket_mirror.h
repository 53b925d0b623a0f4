// The bucket side of the asset store (bucket_layout.h): versions listed,
// records and files read (each file checked against its record's size and
// SHA-256, so a partial or corrupt object is never parsed), versions and
// tombstones written, old versions pruned. Knows nothing of the catalog.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "armature/base/status.h"
#include "armature/engine/io/asset.h"
#include "server/assets/bucket/bucket_layout.h"
#include "server/assets/bucket/object_store.h"

namespace armature::server {

class BucketMirror {
 public:
  BucketMirror(std::unique_ptr<ObjectStore> store, std::string prefix)
      : store_(std::move(store)), prefix_(std::move(prefix)) {}

  // Every name's versions, oldest first (one listing, all pages).
  StatusOr<std::map<std::string, std::vector<std::string>>> Versions();
  StatusOr<VersionRecord> ReadRecord(const std::string& name, const std::string& version);
  // The object's bytes; DATA_LOSS-like INTERNAL "corrupt" when size or hash differ.
  StatusOr<std::string> ReadObject(const StoredObject& object);
  // Writes the files, then the record that makes the version exist. On a
  // failure the files written are deleted again (best effort).
  Status WriteVersion(VersionRecord& version, const std::string& bytes, const ResourceMap& resources);
  Status WriteTombstone(const std::string& name, const std::string& version);
  // Deletes all but the last `keep` versions of `name` (records first, so a
  // version never names missing files). Failures are logged: pruning waits for the next write.
  void Prune(const std::string& name, int keep);

  std::string Describe() const { return store_->Describe() + (prefix_.empty() ? "" : "/" + prefix_); }
  const std::string& prefix() const { return prefix_; }

 private:
  std::unique_ptr<ObjectStore> store_;
  std::string prefix_;
};

}  // namespace armature::server
