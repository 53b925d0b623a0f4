// armature-server assembled: asset store, gRPC services (with health and
// reflection) and the HTTP side, started and stopped together.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <grpcpp/grpcpp.h>
#include <grpcpp/impl/codegen/service_type.h>

#include "armature/base/status.h"
#include "server/assets/asset_store.h"
#include "server/host/config.h"
#include "server/host/gateway/gateway.h"
#include "server/host/auth/bearer_tokens.h"
#include "server/host/http/http_server.h"
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
  // Start's steps, in order.
  Status LoadAccessRules();  // --auth-token-file, --trust-forwarded-for
  Status OpenStore();        // the data dir (demo assets seeded into a fresh one)
  Status StartGrpc(const std::shared_ptr<grpc::ServerCredentials>& credentials);
  // The API services (behind auth gates with a token file) and reflection v1
  // into services_; the API services' names.
  StatusOr<std::vector<std::string>> AddServices();
  Status StartHttp();     // metrics, the gateway and the viewer on the HTTP port
  Status StartGateway();  // the gateway and the viewer on http_

  ServerConfig config_;
  std::unique_ptr<AssetStore> store_;
  std::unique_ptr<Metrics> metrics_;            // outlives the gRPC server, whose interceptors use it
  std::shared_ptr<const BearerTokens> tokens_;  // null: no auth
  gateway::TrustedProxies trusted_proxies_;     // --trust-forwarded-for
  std::vector<std::unique_ptr<grpc::Service>> services_;
  std::unique_ptr<grpc::Server> grpc_;
  std::unique_ptr<gateway::Gateway> gateway_;  // calls grpc_ in-process; serves on http_
  std::unique_ptr<HttpServer> http_;
  int grpc_port_ = 0;
  int http_port_ = -1;
  bool stopped_ = false;
};

}  // namespace armature::server
