// The assets' layout on a bucket, which needs no lock between replicas:
//
//   PREFIX/objects/<name>/<version>/source.<ext>, res<i>.<uri>   immutable files
//   PREFIX/versions/<name>/<version>                             its version record
//
// An import writes its files, then its version record (JSON: the AssetRecord
// and each file's key, size and SHA-256); the record is what makes the
// version exist, so a writer killed in between leaves only unreferenced
// files. A delete writes a record {"deleted": true}, a tombstone. The catalog
// is the latest record of each name, versions ordered as strings:
// "<UTC yyyymmddThhmmss.uuuuuuZ>-<16 hex random>", time first, the random id
// breaking ties, so every replica agrees on the order without talking to
// another. Names are asset names (letters, digits, . _ -): safe in keys.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "armature/base/status.h"
#include "server/assets/bucket/object_store.h"
#include "server/assets/catalog.h"

namespace armature::server {

struct StoredObject {
  std::string key;
  int64_t size = 0;
  std::string sha256;  // hex
};

struct VersionRecord {
  AssetRecord record;  // record.version set; file and resources are the local cache's paths
  bool deleted = false;
  StoredObject source;
  std::map<std::string, StoredObject> resources;  // by uri
};

// A version later than `after` (when given) and than the clock's now.
std::string NewVersion(std::string_view after = "");

std::string VersionsPrefix(const std::string& prefix);
std::string VersionKey(const std::string& prefix, const std::string& name, const std::string& version);
std::string ObjectKey(const std::string& prefix, const std::string& name, const std::string& version,
                      const std::string& file);

// Every version of every name in a listing of VersionsPrefix, oldest first;
// keys that are not version records are ignored.
std::map<std::string, std::vector<std::string>> VersionsByName(const std::vector<ObjectEntry>& listing,
                                                               const std::string& prefix);

std::string VersionRecordToJson(const VersionRecord& v);
// INVALID_ARGUMENT for a record that does not parse (a partial or foreign object).
StatusOr<VersionRecord> VersionRecordFromJson(std::string_view text);

std::string Sha256Hex(std::string_view bytes);

}  // namespace armature::server
