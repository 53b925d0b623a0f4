#include "server/assets/bucket/store_health.h"

#include <nlohmann/json.hpp>

namespace armature::server {

std::string StoreHealthJson(const StoreHealth& health) {
  nlohmann::json j = {{"kind", health.kind}, {"location", health.location}, {"reachable", health.reachable}};
  if (!health.error.empty()) j["error"] = health.error;
  if (health.kind == "bucket") {
    j["serving_cache"] = health.serving_cache;
    j["version_failures"] = health.version_failures;
    j["seconds_since_sync"] = health.seconds_since_sync;
  }
  return j.dump();
}

void CollectStoreMetrics(const StoreHealth& health, PrometheusText& out) {
  const PrometheusText::Labels labels = {{"kind", health.kind}};
  out.Family("armature_store_reachable", "gauge", "1 while the asset store (data dir or bucket) answers, else 0.");
  out.Sample("armature_store_reachable", labels, health.reachable ? 1 : 0);
  out.Family("armature_store_version_failures_total", "counter",
             "Asset versions skipped: unreadable, corrupt or not parsing (the version before keeps serving).");
  out.Sample("armature_store_version_failures_total", labels, static_cast<double>(health.version_failures));
  if (health.kind == "bucket") {
    out.Family("armature_store_sync_age_seconds", "gauge", "Seconds since the bucket was last listed successfully.");
    out.Sample("armature_store_sync_age_seconds", labels, health.seconds_since_sync);
  }
}

}  // namespace armature::server
