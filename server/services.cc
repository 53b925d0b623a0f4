#include "server/services.h"

#include "server/asset_service.h"
#include "server/ik_service.h"
#include "server/pose_service.h"

namespace armature::server {

std::vector<std::unique_ptr<grpc::Service>> MakeServices(AssetStore& store, const Limits& limits) {
  std::vector<std::unique_ptr<grpc::Service>> services;
  services.push_back(std::make_unique<AssetServiceImpl>(store, limits));
  services.push_back(std::make_unique<PoseServiceImpl>(store, limits));
  services.push_back(std::make_unique<IkServiceImpl>(store, limits));
  return services;
}

}  // namespace armature::server
