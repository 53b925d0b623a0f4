// --store's value: s3://HOST:PORT/BUCKET/PREFIX (plain HTTP, as a local MinIO or
// s3rver serves it) or s3+https://HOST[:PORT]/BUCKET/PREFIX; path-style
// addressing, so any host name and bucket names with dots work.
#pragma once

#include <string>
#include <string_view>

#include "armature/base/status.h"

namespace armature::server {

struct StoreLocation {
  std::string scheme;  // "http" or "https"
  std::string host;
  int port = 0;
  std::string bucket;
  // The keys' common start: "" or "a/b/" ("", "/" and "//" all mean the
  // bucket's root; repeated slashes fold to one).
  std::string prefix;

  std::string Endpoint() const { return scheme + "://" + host + ":" + std::to_string(port); }
  std::string Describe() const { return Endpoint() + "/" + bucket + (prefix.empty() ? "" : "/" + prefix); }
};

// INVALID_ARGUMENT naming what is wrong (scheme, host, port, bucket name).
StatusOr<StoreLocation> ParseStoreUrl(std::string_view url);

}  // namespace armature::server
