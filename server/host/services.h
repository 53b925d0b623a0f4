// Every gRPC service armature-server offers. New services are added in
// services.cc only, with MakeService so each carries the name of the proto
// service it implements (the auth gate needs it).
#pragma once

#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include <grpcpp/grpcpp.h>
#include <grpcpp/impl/codegen/service_type.h>

#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"
#include "server/rpc/metrics.h"

namespace armature::server {

struct ServiceEntry {
  std::string name;  // full proto name, e.g. "armature.v1.AssetService"
  std::unique_ptr<grpc::Service> service;
};

// `Generated` is the class protoc made for the service (v1::AssetService),
// `Impl` the implementation of its CallbackService.
template <class Generated, class Impl, class... Args>
ServiceEntry MakeService(Args&&... args) {
  static_assert(std::is_base_of_v<typename Generated::Service, Impl>, "Impl must implement Generated");
  return {Generated::service_full_name(), std::make_unique<Impl>(std::forward<Args>(args)...)};
}

// `tokens_verified`: the services sit behind an auth gate, so per-client
// limits may count a caller by its token.
std::vector<ServiceEntry> MakeServices(AssetStore& store, const Limits& limits, Metrics& metrics, bool tokens_verified);

}  // namespace armature::server
