// Every gRPC service armature-server offers. New services are added in
// services.cc only.
#pragma once

#include <memory>
#include <vector>

#include <grpcpp/grpcpp.h>
#include <grpcpp/impl/codegen/service_type.h>

#include "server/asset_store.h"
#include "server/limits.h"

namespace armature::server {

std::vector<std::unique_ptr<grpc::Service>> MakeServices(AssetStore& store, const Limits& limits);

}  // namespace armature::server
