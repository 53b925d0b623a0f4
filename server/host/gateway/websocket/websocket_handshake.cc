#include "server/host/gateway/websocket/websocket_handshake.h"

#include <algorithm>
#include <cctype>
#include <vector>

#include <httplib.h>

#include "server/host/gateway/common/error_mapping.h"
#include "server/host/gateway/common/request_headers.h"
#include "server/host/gateway/websocket/websocket_framing.h"

namespace armature::server::gateway {
namespace {

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

}  // namespace

bool IsWebSocketUpgrade(const httplib::Request& req) {
  for (const auto& item : HeaderItems(req, "Upgrade"))
    if (Lower(item) == "websocket") return true;
  return false;
}

bool CheckUpgradeRequest(const httplib::Request& req, httplib::Response& res) {
  if (req.method != "GET") {
    WriteError(res, 405, grpc::StatusCode::INVALID_ARGUMENT, "a WebSocket opens with GET, not " + req.method);
    return false;
  }
  // httplib does not read a GET's body, so the session would read it as frames.
  if (req.has_header("Transfer-Encoding") ||
      (req.has_header("Content-Length") && req.get_header_value("Content-Length") != "0")) {
    res.set_header("Connection", "close");
    WriteError(res, 400, grpc::StatusCode::INVALID_ARGUMENT,
               "a WebSocket upgrade carries no body: header " +
                   std::string(req.has_header("Transfer-Encoding")
                                   ? "Transfer-Encoding"
                                   : "Content-Length: " + req.get_header_value("Content-Length")) +
                   " is refused");
    return false;
  }
  bool connection_upgrade = false;
  for (const auto& item : HeaderItems(req, "Connection")) connection_upgrade |= Lower(item) == "upgrade";
  if (!connection_upgrade) {
    WriteError(res, 400, grpc::StatusCode::INVALID_ARGUMENT, "header Connection: must list Upgrade");
    return false;
  }
  if (req.get_header_value("Sec-WebSocket-Version") != "13") {
    res.set_header("Sec-WebSocket-Version", "13");
    WriteError(res, 426, grpc::StatusCode::INVALID_ARGUMENT, "header Sec-WebSocket-Version: only 13 is spoken");
    return false;
  }
  if (!IsValidWebSocketKey(req.get_header_value("Sec-WebSocket-Key"))) {
    WriteError(res, 400, grpc::StatusCode::INVALID_ARGUMENT,
               "header Sec-WebSocket-Key: must be the base64 of 16 bytes");
    return false;
  }
  return true;
}

SessionCredentials CredentialsOf(const httplib::Request& req) {
  SessionCredentials credentials{req.get_header_value("Authorization"), ""};
  const std::vector<std::string> protocols = HeaderItems(req, "Sec-WebSocket-Protocol");
  for (size_t i = 0; i < protocols.size() && credentials.protocol.empty(); ++i) {
    if (protocols[i].rfind("bearer.", 0) == 0 && protocols[i].size() > 7) {
      credentials.protocol = protocols[i];
      if (credentials.authorization.empty()) credentials.authorization = "Bearer " + protocols[i].substr(7);
    } else if (protocols[i] == "bearer" && i + 1 < protocols.size()) {
      credentials.protocol = "bearer";
      if (credentials.authorization.empty()) credentials.authorization = "Bearer " + protocols[i + 1];
    }
  }
  return credentials;
}

std::string SwitchingProtocols(const std::string& key, const std::string& protocol) {
  std::string head =
      "HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Accept: " +
      WebSocketAccept(key) + "\r\n";
  if (!protocol.empty()) head += "Sec-WebSocket-Protocol: " + protocol + "\r\n";
  return head + "\r\n";
}

}  // namespace armature::server::gateway
