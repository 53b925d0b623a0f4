// What health checks and metrics say of the asset store: where the assets
// live and whether that place answers.
#pragma once

#include <cstdint>
#include <string>

#include "server/rpc/metrics.h"

namespace armature::server {

// Where the assets live and whether that place answers (health, metrics).
struct StoreHealth {
  std::string kind;      // "data_dir" or "bucket"
  std::string location;  // the data dir, or the bucket's endpoint/bucket/prefix
  bool reachable = true;
  std::string error;              // the last failure while unreachable
  bool serving_cache = false;     // started from the cache, the bucket unreachable
  int64_t version_failures = 0;   // versions skipped: unreadable, corrupt or not parsing
  double seconds_since_sync = 0;  // since the bucket was last listed successfully
};

// {"kind":…,"location":…,"reachable":…,…} for /healthz.
std::string StoreHealthJson(const StoreHealth& health);
// armature_store_reachable, armature_store_version_failures_total, armature_store_sync_age_seconds.
void CollectStoreMetrics(const StoreHealth& health, PrometheusText& out);

}  // namespace armature::server
