#include "server/host/services.h"

#include "server/assets/asset_service.h"
#include "server/authoring/authoring_service.h"
#include "server/crowd/crowd_service.h"
#include "server/deform/deform_service.h"
#include "server/ik/ik_service.h"
#include "server/mesh/mesh_service.h"
#include "server/pose/pose_service.h"
#include "server/rpc/work/heavy_call_pool.h"
#include "server/rpc/streams/session_admission.h"
#include "server/rpc/streams/stream_admission.h"

namespace armature::server {

std::vector<ServiceEntry> MakeServices(AssetStore& store, const Limits& limits, Metrics& metrics,
                                       bool tokens_verified) {
  // Sessions of every kind share one admission (per-client and total limits, the gauge).
  auto sessions = std::make_shared<SessionAdmission>(limits, tokens_verified);
  metrics.AddCollector([sessions](PrometheusText& out) { sessions->Collect(out); });
  // Streams of every RPC share one admission (--max-streams-per-client, --max-streams).
  auto streams = std::make_shared<StreamAdmission>(limits, tokens_verified);
  std::vector<ServiceEntry> services;
  services.push_back(MakeService<v1::AssetService, AssetServiceImpl>(store, limits));
  // Heavy unary calls of every service share one bounded pool (--heavy-threads, --heavy-queue).
  auto heavy = std::make_shared<HeavyCallPool>(limits);
  services.push_back(MakeService<v1::PoseService, PoseServiceImpl>(store, limits, sessions, streams, heavy));
  auto deform_cache = std::make_shared<DeformerCache>(static_cast<size_t>(limits.deform_cache_bytes));
  metrics.AddCollector([deform_cache](PrometheusText& out) { deform_cache->Collect(out); });
  services.push_back(MakeService<v1::DeformService, DeformServiceImpl>(store, limits, sessions, streams, deform_cache));
  services.push_back(MakeService<v1::IkService, IkServiceImpl>(store, limits, sessions, streams));
  services.push_back(MakeService<v1::MeshService, MeshServiceImpl>(store, limits, streams));
  services.push_back(MakeService<v1::AuthoringService, AuthoringServiceImpl>(store, limits));
  // Crowds share the server-wide character cap (--max-crowd-characters-total) and their counters.
  auto crowds = std::make_shared<CrowdTotals>(limits.max_crowd_characters_total);
  metrics.AddCollector([crowds](PrometheusText& out) { crowds->Collect(out); });
  services.push_back(MakeService<v1::CrowdService, CrowdServiceImpl>(store, limits, sessions, streams, crowds));
  return services;
}

}  // namespace armature::server
