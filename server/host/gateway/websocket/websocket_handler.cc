#include "server/host/gateway/websocket/websocket_handler.h"

#include <httplib.h>

#include "server/host/gateway/common/error_mapping.h"
#include "server/host/gateway/websocket/upgraded_connection.h"
#include "server/host/gateway/websocket/websocket_handshake.h"
#include "server/host/gateway/websocket/websocket_session.h"

namespace armature::server::gateway {

void WebSocketHandler::Handle(const httplib::Request& req, httplib::Response& res, const RequestPath& path) {
  auto route = routes_.Match("POST", path);
  if (!route || !route->binding->client_streaming() || !route->binding->server_streaming())
    return WriteError(res, 404, grpc::StatusCode::NOT_FOUND,
                      "no session at " + req.path +
                          ": WebSockets reach the bidirectional methods (IkSession, DeformSession, PlaybackSession, "
                          "CrowdSession) on their REST paths, e.g. /v1/skeletons/{skeleton}:ikSession");
  const HttpBinding& binding = *route->binding;
  if (!CheckUpgradeRequest(req, res)) return;
  const SessionCredentials credentials = CredentialsOf(req);
  if (grpc::Status st = calls_.Authenticate(credentials.authorization); !st.ok()) return WriteError(res, st);
  if (calls_.calls().draining()) return WriteError(res, ShuttingDown());

  const GatewayOptions& options = calls_.options();
  std::optional<UpgradedConnection> connection = UpgradedConnection::TakeOver(req, options.websocket_write_timeout);
  if (!connection)
    return WriteError(res, grpc::Status(grpc::StatusCode::INTERNAL, "could not find the connection's socket"));
  httplib::Request forwarded = req;
  if (!credentials.authorization.empty()) forwarded.set_header("Authorization", credentials.authorization);
  forwarded.headers.erase("grpc-timeout");  // a session has no deadline; it ends with its client
  std::unique_ptr<grpc::ClientContext> context;
  if (auto st = calls_.MakeContext(forwarded, /*server_streaming=*/true, &context); !st.ok())
    return WriteError(res, st);
  std::unique_ptr<BidiCall> call;
  if (auto st = calls_.StartSession(binding.grpc_method(), std::move(context), &call); !st.ok())
    return WriteError(res, st);

  connection->SendImmediately();
  if (connection->Write(SwitchingProtocols(req.get_header_value("Sec-WebSocket-Key"), credentials.protocol))) {
    WebSocketSession session(*connection,
                             {&binding, route->variables, &calls_.Prototype(binding.method->input_type()),
                              &calls_.Prototype(binding.method->output_type())},
                             *call, options);
    session.Run();
  }
  call->Cancel();
  calls_.EndSession(call.get());
  connection->Close();
  res.status = 101;
}

}  // namespace armature::server::gateway
