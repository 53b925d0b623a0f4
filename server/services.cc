#include "server/services.h"

#include "server/asset_service.h"
#include "server/mesh_service.h"
#include "server/pose_service.h"

namespace armature::server {

std::vector<ServiceEntry> MakeServices(AssetStore& store, const Limits& limits) {
  std::vector<ServiceEntry> services;
  services.push_back(MakeService<v1::AssetService, AssetServiceImpl>(store, limits));
  services.push_back(MakeService<v1::PoseService, PoseServiceImpl>(store, limits));
  services.push_back(MakeService<v1::MeshService, MeshServiceImpl>(store, limits));
  return services;
}

}  // namespace armature::server
