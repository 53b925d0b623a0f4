// A gRPC server interceptor that sees every call (REST calls through the
// in-process channel included): it counts calls and their latency in the
// Metrics and writes one log line per call with its request id.
#pragma once

#include <grpcpp/support/server_interceptor.h>

#include "server/rpc/metrics.h"

namespace armature::server {

// Request ids come from the `x-request-id` metadata, or are made here; the
// id is sent back in the response's initial metadata. Health checks log at
// debug level, every other call at info.
class RpcObserverFactory final : public grpc::experimental::ServerInterceptorFactoryInterface {
 public:
  explicit RpcObserverFactory(Metrics& metrics) : metrics_(metrics) {}
  grpc::experimental::Interceptor* CreateServerInterceptor(grpc::experimental::ServerRpcInfo* info) override;

 private:
  Metrics& metrics_;
};

}  // namespace armature::server
