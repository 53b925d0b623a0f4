// What the asset store needs of an object store (S3 and compatible servers):
// whole objects put, read, listed under a prefix and deleted. Every call is
// bounded in time; a store that cannot be reached answers UNAVAILABLE naming
// its endpoint, denied credentials PERMISSION_DENIED, a missing key NOT_FOUND.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "armature/base/status.h"

namespace armature::server {

struct ObjectEntry {
  std::string key;
  int64_t size = 0;
};

class ObjectStore {
 public:
  virtual ~ObjectStore() = default;
  virtual Status Put(const std::string& key, std::string_view bytes) = 0;
  virtual StatusOr<std::string> Get(const std::string& key) = 0;
  // Every key under `prefix`, in key order, all pages read.
  virtual StatusOr<std::vector<ObjectEntry>> List(const std::string& prefix) = 0;
  virtual Status Delete(const std::string& key) = 0;
  // Where it is, for messages: "http://host:port/bucket".
  virtual std::string Describe() const = 0;
};

}  // namespace armature::server
