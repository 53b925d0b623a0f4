// Bidirectional sessions (IkSession, DeformSession, PlaybackSession) over a
// WebSocket on their REST path: GET /v1/skeletons/{skeleton}:ikSession with
// `Upgrade: websocket`. The handshake is checked and its token too
// (websocket_handshake.h), the connection taken over from httplib
// (upgraded_connection.h), the 101 written and the session run in the
// handler's thread (websocket_session.h); when it ends, the connection is
// closed under httplib, so the response httplib then writes fails harmlessly.
// The session is the gRPC method called through the call factory, so auth,
// limits, session counting and metrics are gRPC's; it holds an HTTP thread
// and counts as one of the gateway's open streams, so REST keeps its share.
#pragma once

#include "server/host/gateway/common/call_factory.h"
#include "server/host/gateway/rest/route_table.h"

namespace httplib {
struct Request;
struct Response;
}  // namespace httplib

namespace armature::server::gateway {

class WebSocketHandler {
 public:
  // Both outlive the handler.
  WebSocketHandler(const RouteTable& routes, CallFactory& calls) : routes_(routes), calls_(calls) {}

  // An upgrade request on `path` (IsWebSocketUpgrade): the whole session.
  void Handle(const httplib::Request& req, httplib::Response& res, const RequestPath& path);

 private:
  const RouteTable& routes_;
  CallFactory& calls_;
};

}  // namespace armature::server::gateway
