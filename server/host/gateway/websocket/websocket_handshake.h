// A WebSocket upgrade request read (RFC 6455 §4.2): the checks of its
// headers, the bearer token a browser sends as a subprotocol, and the 101
// that accepts it. The frames that follow are websocket_framing's.
#pragma once

#include <string>

namespace httplib {
struct Request;
struct Response;
}  // namespace httplib

namespace armature::server::gateway {

// True when the request asks for `Upgrade: websocket`.
bool IsWebSocketUpgrade(const httplib::Request& req);

// Checks an upgrade's method and headers (GET, no body, Connection: Upgrade,
// version 13, a valid key); false once it has written the error.
bool CheckUpgradeRequest(const httplib::Request& req, httplib::Response& res);

// Browsers cannot set Authorization on a WebSocket: the token may come as
// the subprotocol "bearer.<token>" or as the pair "bearer", "<token>".
struct SessionCredentials {
  std::string authorization;  // the Authorization header, else "Bearer <token>" from the subprotocol
  std::string protocol;       // the subprotocol the 101 names ("" for none)
};
SessionCredentials CredentialsOf(const httplib::Request& req);

// The 101 Switching Protocols response's head for the request's key.
std::string SwitchingProtocols(const std::string& key, const std::string& protocol);

}  // namespace armature::server::gateway
