#include "server/services.h"

#include "server/asset_service.h"
#include "server/deform_service.h"
#include "server/ik_service.h"
#include "server/mesh_service.h"
#include "server/pose_service.h"
#include "server/session_admission.h"

namespace armature::server {

std::vector<ServiceEntry> MakeServices(AssetStore& store, const Limits& limits, Metrics& metrics) {
  // Sessions of every kind share one admission (per-client and total limits, the gauge).
  auto sessions = std::make_shared<SessionAdmission>(limits);
  metrics.AddCollector([sessions](PrometheusText& out) { sessions->Collect(out); });
  std::vector<ServiceEntry> services;
  services.push_back(MakeService<v1::AssetService, AssetServiceImpl>(store, limits));
  services.push_back(MakeService<v1::PoseService, PoseServiceImpl>(store, limits));
  auto deform_cache = std::make_shared<DeformerCache>(static_cast<size_t>(limits.deform_cache_bytes));
  metrics.AddCollector([deform_cache](PrometheusText& out) { deform_cache->Collect(out); });
  services.push_back(MakeService<v1::DeformService, DeformServiceImpl>(store, limits, sessions, deform_cache));
  services.push_back(MakeService<v1::IkService, IkServiceImpl>(store, limits, sessions));
  services.push_back(MakeService<v1::MeshService, MeshServiceImpl>(store, limits));
  return services;
}

}  // namespace armature::server
