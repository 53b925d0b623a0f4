// armature-server assembled: asset store, gRPC services (with health and
// reflection) and the HTTP side, started and stopped together.
#pragma once

#include <memory>

#include <grpcpp/grpcpp.h>
#include <grpcpp/impl/codegen/service_type.h>

#include "armature/base/status.h"
#include "server/assets/asset_store.h"
#include "server/host/config.h"
#include "server/host/gateway/gateway.h"
#include "server/host/bearer_tokens.h"
#include "server/host/http_server.h"
#include "server/rpc/metrics.h"

namespace armature::server {

class ArmatureServer {
 public:
  static StatusOr<std::unique_ptr<ArmatureServer>> Start(const ServerConfig& config);
  ~ArmatureServer();

  // Stops accepting, lets in-flight calls finish for the grace period, then cancels them.
  void Shutdown();

  int grpc_port() const { return grpc_port_; }
  int http_port() const { return http_port_; }
  AssetStore& store() { return *store_; }
  Metrics& metrics() { return *metrics_; }

 private:
  ArmatureServer() = default;
  Status StartGateway();  // the REST gateway and the viewer on http_

  ServerConfig config_;
  std::unique_ptr<AssetStore> store_;
  std::unique_ptr<Metrics> metrics_;              // outlives the gRPC server, whose interceptors use it
  std::shared_ptr<const BearerTokens> tokens_;  // null: no auth
  gateway::TrustedProxies trusted_proxies_;      // --trust-forwarded-for
  std::vector<std::unique_ptr<grpc::Service>> services_;
  std::unique_ptr<grpc::Server> grpc_;
  std::unique_ptr<gateway::Gateway> gateway_;  // calls grpc_ in-process; serves on http_
  std::unique_ptr<HttpServer> http_;
  int grpc_port_ = 0;
  int http_port_ = -1;
  bool stopped_ = false;
};

}  // namespace armature::server
