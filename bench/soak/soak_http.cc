#include "soak_http.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "server/host/gateway/grpc_web/grpc_web_framing.h"
#include "server/host/gateway/websocket/websocket_framing.h"

namespace armature::soak {
namespace {

constexpr int kTimeoutMs = 10000;

grpc::Status Failed(const std::string& what) { return {grpc::StatusCode::UNKNOWN, what}; }

// The gateway's JSON error body, {"code": N, "message": "..."}, as a status.
grpc::Status FromErrorJson(int http_status, const std::string& body) {
  const auto j = nlohmann::json::parse(body, nullptr, false);
  if (!j.is_object() || !j.contains("code") || !j["code"].is_number_integer())
    return Failed("HTTP " + std::to_string(http_status) + " without the error body: " + body.substr(0, 200));
  return {static_cast<grpc::StatusCode>(j["code"].get<int>()), j.value("message", "")};
}

uint32_t BigEndian32(const std::string& s, size_t at) {
  uint32_t n = 0;
  for (size_t k = 0; k < 4; ++k) n = (n << 8) | static_cast<unsigned char>(s[at + k]);
  return n;
}

// A blocking loopback socket speaking RFC 6455 as a client: masked frames out.
class WebSocket {
 public:
  explicit WebSocket(int port) : fd_(::socket(AF_INET, SOCK_STREAM, 0)) {
    const int one = 1;
    ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) == 0;
  }
  ~WebSocket() { ::close(fd_); }

  // The upgrade; the answer's status code (101 when upgraded).
  int Upgrade(const std::string& path) {
    if (!connected_) return 0;
    Send("GET " + path +
         " HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
         "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n");
    std::string head;
    size_t end;
    while ((end = head.find("\r\n\r\n")) == std::string::npos && head.size() < 8192) {
      const std::string bytes = ReadSome();
      if (bytes.empty()) return 0;
      head += bytes;
    }
    if (end != std::string::npos) reader_.Feed(std::string_view(head).substr(end + 4));  // frames sent at once
    return head.size() > 12 ? std::atoi(head.c_str() + 9) : 0;
  }
  // A masked frame, as every client frame must be (the server's own framing, client side).
  void SendFrame(server::gateway::WsOpcode opcode, const std::string& payload) {
    std::string frame;
    server::gateway::AppendWebSocketFrame(opcode, payload, &frame, true, static_cast<uint32_t>(rng_()));
    Send(frame);
  }
  // The next message or control frame; kNone when nothing whole came within the timeout.
  server::gateway::WsEvent Receive() {
    for (;;) {
      server::gateway::WsEvent event = reader_.Next();
      if (event.kind != server::gateway::WsEvent::Kind::kNone) return event;
      const std::string bytes = ReadSome();
      if (bytes.empty()) return event;
      reader_.Feed(bytes);
    }
  }

 private:
  void Send(const std::string& bytes) { (void)!::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL); }
  std::string ReadSome() {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, kTimeoutMs) <= 0) return "";
    char buffer[16384];
    const ssize_t r = ::recv(fd_, buffer, sizeof(buffer), 0);
    return r > 0 ? std::string(buffer, static_cast<size_t>(r)) : "";
  }

  int fd_;
  bool connected_ = false;
  std::mt19937 rng_{11};
  server::gateway::WebSocketReader reader_{64u << 20, /*require_mask=*/false};
};

}  // namespace

grpc::Status HttpTransports::GrpcWeb(const std::string& method_path, const google::protobuf::Message& request,
                                     google::protobuf::Message& response) {
  httplib::Client http("127.0.0.1", port_);
  http.set_read_timeout(kTimeoutMs / 1000);
  std::string body;
  server::gateway::AppendGrpcWebFrame(server::gateway::kGrpcWebDataFlag, request.SerializeAsString(), &body);
  const auto r = http.Post(method_path, {{"X-Grpc-Web", "1"}}, body, "application/grpc-web+proto");
  if (!r) return Failed("gRPC-Web: no answer (" + httplib::to_string(r.error()) + ")");
  if (r->status != 200) return Failed("gRPC-Web: HTTP " + std::to_string(r->status));
  // Frames: 0x00 data, 0x80 trailers ("grpc-status: N\r\ngrpc-message: ...").
  int code = r->has_header("grpc-status") ? std::stoi(r->get_header_value("grpc-status")) : -1;
  std::string trailers;
  for (size_t at = 0; at + 5 <= r->body.size();) {
    const uint32_t n = BigEndian32(r->body, at + 1);
    if (at + 5 + n > r->body.size()) return Failed("gRPC-Web: a frame runs past the body");
    const std::string payload = r->body.substr(at + 5, n);
    if (r->body[at] & server::gateway::kGrpcWebTrailerFlag)
      trailers = payload;
    else if (!response.ParseFromString(payload))
      return Failed("gRPC-Web: the message does not parse");
    at += 5 + n;
  }
  if (const size_t s = trailers.find("grpc-status:"); s != std::string::npos) code = std::stoi(trailers.substr(s + 12));
  if (code < 0) return Failed("gRPC-Web: no grpc-status");
  std::string message_text;
  if (const size_t m = trailers.find("grpc-message:"); m != std::string::npos)
    message_text = server::gateway::PercentDecode(trailers.substr(m + 13, trailers.find("\r\n", m) - m - 13));
  return {static_cast<grpc::StatusCode>(code), message_text};
}

grpc::Status HttpTransports::RestBinary(const std::string& path, const google::protobuf::Message& request,
                                        google::protobuf::Message& response) {
  httplib::Client http("127.0.0.1", port_);
  http.set_read_timeout(kTimeoutMs / 1000);
  const auto r =
      http.Post(path, {{"Accept", "application/x-protobuf"}}, request.SerializeAsString(), "application/x-protobuf");
  if (!r) return Failed("binary REST: no answer (" + httplib::to_string(r.error()) + ")");
  if (r->status != 200) return FromErrorJson(r->status, r->body);
  if (r->get_header_value("Content-Type") != "application/x-protobuf")
    return Failed("binary REST: answered as " + r->get_header_value("Content-Type"));
  return response.ParseFromString(r->body) ? grpc::Status::OK : Failed("binary REST: the answer does not parse");
}

grpc::Status HttpTransports::WebSocketSession(const std::string& path, const std::vector<std::string>& messages) {
  WebSocket ws(port_);
  if (const int status = ws.Upgrade(path); status != 101)
    return Failed("WebSocket: the upgrade was answered " + std::to_string(status));
  using server::gateway::WsEvent;
  using server::gateway::WsOpcode;
  for (const std::string& m : messages) {
    ws.SendFrame(WsOpcode::kBinary, m);
    const WsEvent answer = ws.Receive();
    if (answer.kind == WsEvent::Kind::kMessage && answer.opcode == WsOpcode::kText)
      return FromErrorJson(0, answer.payload);  // a failed session: its status, then a close
    if (answer.kind != WsEvent::Kind::kMessage) return Failed("WebSocket: no answer to a message");
  }
  ws.SendFrame(WsOpcode::kClose, server::gateway::WebSocketClosePayload(server::gateway::kWsCloseNormal, ""));
  if (ws.Receive().kind != WsEvent::Kind::kClose) return Failed("WebSocket: the close was not answered");
  return grpc::Status::OK;
}

}  // namespace armature::soak
