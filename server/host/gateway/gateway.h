// The HTTP side of the API: REST/JSON (rest/), gRPC-Web (grpc_web/) and
// WebSocket sessions (websocket/), each its own handler over one call
// factory (common/call_factory.h) that calls the server's own gRPC services
// through an in-process channel. So the gRPC side's checks apply to every
// protocol as they are: validation, limits, the auth gate (the gateway also
// checks the token itself, before a body is read) and the metrics and
// request log of the RPC observer. The Gateway only routes: it compiles the
// routes, adds CORS and the shared error answers, and hands each request to
// its protocol's handler. A new annotated RPC needs no code here.
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>
#include <grpcpp/grpcpp.h>

#include "armature/base/status.h"
#include "server/host/gateway/common/call_factory.h"
#include "server/host/gateway/common/gateway_options.h"
#include "server/host/gateway/cors.h"
#include "server/host/gateway/grpc_web/grpc_web_handler.h"
#include "server/host/gateway/rest/rest_handler.h"
#include "server/host/gateway/rest/route_table.h"
#include "server/host/gateway/websocket/websocket_handler.h"

namespace httplib {
class Server;
struct Request;
struct Response;
class ContentReader;
}  // namespace httplib

namespace armature::server::gateway {

class Gateway {
 public:
  // Compiles the bindings of every method of `services`. INVALID_ARGUMENT for
  // a malformed rule or two methods claiming the same HTTP method and path.
  // `factory` makes the request and response messages (generated or dynamic).
  static StatusOr<std::unique_ptr<Gateway>> Create(
      const std::vector<const google::protobuf::ServiceDescriptor*>& services,
      google::protobuf::MessageFactory* factory, std::shared_ptr<grpc::Channel> channel, GatewayOptions options);
  Gateway(const Gateway&) = delete;  // the handlers hold its routes and call factory
  Gateway& operator=(const Gateway&) = delete;

  // Adds CORS, OPTIONS, /openapi.json, gRPC-Web (POST /armature.v1.<Service>/<Method>,
  // every method of `services`) and the REST routes to `http`. Routes
  // registered before stay first; static files still win for GET.
  void Register(httplib::Server& http);

  // Shutdown, first step: new REST calls get 503 from now on.
  void BeginDrain() { calls_.calls().BeginDrain(); }
  // Lets the calls in flight finish until `deadline`, then cancels the rest.
  // Call before shutting the gRPC server down, which drops in-process calls.
  void Drain(std::chrono::system_clock::time_point deadline) { calls_.calls().Drain(deadline); }

  const std::vector<HttpBinding>& bindings() const { return routes_.bindings(); }

 private:
  Gateway(RouteTable routes, const std::vector<const google::protobuf::ServiceDescriptor*>& services,
          google::protobuf::MessageFactory* factory, std::shared_ptr<grpc::Channel> channel, GatewayOptions options);
  // Before routing: CORS headers, request ids, refused framing, OPTIONS answered.
  void RegisterPreRouting(httplib::Server& http);
  // A request on an API path: a WebSocket upgrade or REST.
  void HandleApiRequest(const httplib::Request& req, httplib::Response& res, const httplib::ContentReader* reader);

  CallFactory calls_;
  CorsPolicy cors_;
  RouteTable routes_;
  std::string openapi_;  // /openapi.json, the REST routes described
  RestHandler rest_;
  GrpcWebHandler grpc_web_;
  WebSocketHandler websocket_;
};

}  // namespace armature::server::gateway
