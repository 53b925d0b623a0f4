// Bidirectional sessions (IkSession, DeformSession, PlaybackSession) over a
// WebSocket on their REST path: GET /v1/skeletons/{skeleton}:ikSession with
// `Upgrade: websocket`. cpp-httplib 0.11 knows nothing of WebSockets, so the
// handler takes the connection over: it finds the socket (the TLS session, or
// the descriptor whose two addresses are the request's), writes the 101
// itself and runs the session in the handler's thread, one poll() over the
// non-blocking socket and the call. When it returns, the connection is closed under
// httplib (an unconnected socket takes its descriptor), so the response
// httplib then writes fails harmlessly.
//
// Each text frame is one JSON request message (the first one also takes the
// path's fields), binary frames the proto encoding; answers use the encoding
// of the latest request. A failed call ends with a text frame
// {"code":…,"message":…} and a close frame with code 4000 + the gRPC code.
// The session is the gRPC method called over the in-process channel, so auth,
// limits, session counting and metrics are gRPC's; it holds an HTTP thread
// and counts as one of the gateway's open streams, so REST keeps its share.
#include <fcntl.h>
#include <netdb.h>
#include <openssl/ssl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include <httplib.h>
#include <spdlog/spdlog.h>

#include "armature/base/utf8.h"
#include "server/host/gateway/bidi_call.h"
#include "server/host/gateway/error_mapping.h"
#include "server/host/gateway/gateway.h"
#include "server/host/gateway/json_codec.h"
#include "server/host/gateway/websocket_framing.h"

namespace armature::server::gateway {
namespace {

namespace pb = google::protobuf;
using Clock = std::chrono::steady_clock;

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

// The comma-separated items of every value of header `name`, trimmed.
std::vector<std::string> HeaderItems(const httplib::Request& req, const char* name) {
  std::vector<std::string> items;
  for (size_t i = 0; i < req.get_header_value_count(name); ++i) {
    const std::string value = req.get_header_value(name, i);
    size_t start = 0;
    while (start <= value.size()) {
      const size_t end = std::min(value.find(',', start), value.size());
      std::string item = value.substr(start, end - start);
      item.erase(0, item.find_first_not_of(" \t"));
      item.erase(item.find_last_not_of(" \t") + 1);
      if (!item.empty()) items.push_back(std::move(item));
      start = end + 1;
    }
  }
  return items;
}

// "ip", port of a socket address, as cpp-httplib prints them.
bool AddressOf(const sockaddr_storage& addr, socklen_t len, std::string* ip, int* port) {
  char host[NI_MAXHOST], serv[NI_MAXSERV];
  if (getnameinfo(reinterpret_cast<const sockaddr*>(&addr), len, host, sizeof(host), serv, sizeof(serv),
                  NI_NUMERICHOST | NI_NUMERICSERV) != 0)
    return false;
  *ip = host;
  *port = std::atoi(serv);
  return true;
}

// The descriptor of the request's TCP connection: the one socket whose peer
// and local addresses are the request's (a TCP connection is its 4-tuple).
int FindConnectionFd(const httplib::Request& req) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd", ec)) {
    const int fd = std::atoi(entry.path().filename().c_str());
    struct stat st {};
    if (fstat(fd, &st) != 0 || !S_ISSOCK(st.st_mode)) continue;
    sockaddr_storage addr{};
    socklen_t len = sizeof(addr);
    std::string ip;
    int port = 0;
    if (getpeername(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0 || !AddressOf(addr, len, &ip, &port) ||
        port != req.remote_port || ip != req.remote_addr)
      continue;
    len = sizeof(addr);
    if (getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0 || !AddressOf(addr, len, &ip, &port) ||
        port != req.local_port || ip != req.local_addr)
      continue;
    return fd;
  }
  return -1;
}

// The connection, plain or TLS, on a non-blocking socket: a read takes what
// has come and never waits (half a TLS record waits in OpenSSL for the
// rest), so the session's writes never wait on its reads; a write waits for
// room at most `write_timeout` in all.
struct Wire {
  static constexpr ssize_t kNothingYet = -2;

  int fd = -1;
  SSL* ssl = nullptr;
  std::chrono::milliseconds write_timeout{10000};

  bool Buffered() const { return ssl && SSL_pending(ssl) > 0; }
  // >0 bytes read, kNothingYet, 0 the peer closed, -1 an error.
  ssize_t Read(char* buf, size_t n) const {
    if (!ssl) {
      const ssize_t r = ::recv(fd, buf, n, 0);
      return r >= 0 ? r : (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) ? kNothingYet : -1;
    }
    const int r = SSL_read(ssl, buf, static_cast<int>(std::min<size_t>(n, 1 << 30)));
    if (r > 0) return r;
    switch (SSL_get_error(ssl, r)) {
      case SSL_ERROR_ZERO_RETURN: return 0;
      case SSL_ERROR_WANT_READ:
      case SSL_ERROR_WANT_WRITE: return kNothingYet;
      default: return -1;
    }
  }
  bool Write(std::string_view data) const {
    const auto deadline = Clock::now() + write_timeout;
    while (!data.empty()) {
      short want = POLLOUT;
      if (ssl) {
        const int w = SSL_write(ssl, data.data(), static_cast<int>(std::min<size_t>(data.size(), 1 << 30)));
        if (w > 0) {
          data.remove_prefix(static_cast<size_t>(w));
          continue;
        }
        const int e = SSL_get_error(ssl, w);
        if (e != SSL_ERROR_WANT_WRITE && e != SSL_ERROR_WANT_READ) return false;
        if (e == SSL_ERROR_WANT_READ) want = POLLIN;
      } else {
        const ssize_t w = ::send(fd, data.data(), data.size(), MSG_NOSIGNAL);
        if (w >= 0) {
          data.remove_prefix(static_cast<size_t>(w));
          continue;
        }
        if (errno == EINTR) continue;
        if (errno != EAGAIN && errno != EWOULDBLOCK) return false;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      pollfd p{fd, want, 0};
      if (left <= 0 || ::poll(&p, 1, static_cast<int>(left)) <= 0) return false;
    }
    return true;
  }
};

}  // namespace

bool IsWebSocketUpgrade(const httplib::Request& req) {
  for (const auto& item : HeaderItems(req, "Upgrade"))
    if (Lower(item) == "websocket") return true;
  return false;
}

void Gateway::HandleWebSocket(const httplib::Request& req, httplib::Response& res, const RequestPath& path) {
  auto route = Match("POST", path);
  if (!route || !route->binding->client_streaming() || !route->binding->server_streaming())
    return WriteError(res, 404, grpc::StatusCode::NOT_FOUND,
                      "no session at " + req.path +
                          ": WebSockets reach the bidirectional methods (IkSession, DeformSession, PlaybackSession) "
                          "on their REST paths, e.g. /v1/skeletons/{skeleton}:ikSession");
  const HttpBinding& binding = *route->binding;
  if (req.method != "GET")
    return WriteError(res, 405, grpc::StatusCode::INVALID_ARGUMENT, "a WebSocket opens with GET, not " + req.method);
  // httplib does not read a GET's body, so the session would read it as frames.
  if (req.has_header("Transfer-Encoding") ||
      (req.has_header("Content-Length") && req.get_header_value("Content-Length") != "0")) {
    res.set_header("Connection", "close");
    return WriteError(res, 400, grpc::StatusCode::INVALID_ARGUMENT,
                      "a WebSocket upgrade carries no body: header " +
                          std::string(req.has_header("Transfer-Encoding") ? "Transfer-Encoding" : "Content-Length: " +
                                                                                 req.get_header_value("Content-Length")) +
                          " is refused");
  }
  bool connection_upgrade = false;
  for (const auto& item : HeaderItems(req, "Connection")) connection_upgrade |= Lower(item) == "upgrade";
  if (!connection_upgrade)
    return WriteError(res, 400, grpc::StatusCode::INVALID_ARGUMENT, "header Connection: must list Upgrade");
  if (req.get_header_value("Sec-WebSocket-Version") != "13") {
    res.set_header("Sec-WebSocket-Version", "13");
    return WriteError(res, 426, grpc::StatusCode::INVALID_ARGUMENT, "header Sec-WebSocket-Version: only 13 is spoken");
  }
  const std::string key = req.get_header_value("Sec-WebSocket-Key");
  if (!IsValidWebSocketKey(key))
    return WriteError(res, 400, grpc::StatusCode::INVALID_ARGUMENT,
                      "header Sec-WebSocket-Key: must be the base64 of 16 bytes");

  // Browsers cannot set Authorization on a WebSocket: the token may come as
  // the subprotocol "bearer.<token>" or as the pair "bearer", "<token>".
  std::string authorization = req.get_header_value("Authorization");
  std::string protocol;
  const auto protocols = HeaderItems(req, "Sec-WebSocket-Protocol");
  for (size_t i = 0; i < protocols.size() && protocol.empty(); ++i) {
    if (protocols[i].rfind("bearer.", 0) == 0 && protocols[i].size() > 7) {
      protocol = protocols[i];
      if (authorization.empty()) authorization = "Bearer " + protocols[i].substr(7);
    } else if (protocols[i] == "bearer" && i + 1 < protocols.size()) {
      protocol = "bearer";
      if (authorization.empty()) authorization = "Bearer " + protocols[i + 1];
    }
  }
  if (options_.tokens) {
    if (Status st = options_.tokens->Check(authorization); !st.ok())
      return WriteError(res, grpc::Status(grpc::StatusCode::UNAUTHENTICATED, st.message()));
  }
  if (calls_.draining())
    return WriteError(res, grpc::Status(grpc::StatusCode::UNAVAILABLE, "the server is shutting down"));

  Wire wire;
  if (req.ssl) {
    wire.ssl = const_cast<SSL*>(req.ssl);
    wire.fd = SSL_get_fd(wire.ssl);
  } else {
    wire.fd = FindConnectionFd(req);
  }
  if (wire.fd < 0)
    return WriteError(res, grpc::Status(grpc::StatusCode::INTERNAL, "could not find the connection's socket"));
  ::fcntl(wire.fd, F_SETFL, ::fcntl(wire.fd, F_GETFL) | O_NONBLOCK);  // see Wire
  wire.write_timeout = options_.websocket_write_timeout;

  httplib::Request forwarded = req;
  if (!authorization.empty()) forwarded.set_header("Authorization", authorization);
  forwarded.headers.erase("grpc-timeout");  // a session has no deadline; it ends with its client
  std::unique_ptr<grpc::ClientContext> context;
  if (auto st = MakeContext(forwarded, /*server_streaming=*/true, &context); !st.ok()) return WriteError(res, st);

  if (open_streams_.fetch_add(1) >= options_.max_streams) {
    --open_streams_;
    return WriteError(res, grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                                        "too many open streams and sessions (" + std::to_string(options_.max_streams) +
                                            "); try again later"));
  }
  std::unique_ptr<BidiCall> call = BidiCall::Start(*stub_, binding.grpc_method(), std::move(context));
  if (!calls_.Add(call.get())) {
    --open_streams_;
    return WriteError(res, grpc::Status(grpc::StatusCode::UNAVAILABLE, "the server is shutting down"));
  }

  std::string handshake =
      "HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Accept: " +
      WebSocketAccept(key) + "\r\n";
  if (!protocol.empty()) handshake += "Sec-WebSocket-Protocol: " + protocol + "\r\n";
  handshake += "\r\n";
  // Each frame goes out at once (no Nagle wait for the ACK of the previous one).
  const int one = 1;
  ::setsockopt(wire.fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
  if (wire.Write(handshake)) RunWebSocketSession(wire.fd, wire.ssl, binding, route->variables, *call);
  call->Cancel();
  calls_.Remove(call.get());
  --open_streams_;
  // Lingering close: our FIN after the close frame, then what the client still
  // sends is read and dropped until it closes too (or 2 s pass), so that no
  // reset destroys the close frame before the client has read it.
  ::shutdown(wire.fd, SHUT_WR);
  const auto linger_until = Clock::now() + std::chrono::seconds(2);
  for (char sink[16384];;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(linger_until - Clock::now()).count();
    pollfd p{wire.fd, POLLIN, 0};
    if (left <= 0 || ::poll(&p, 1, static_cast<int>(left)) <= 0 || ::recv(wire.fd, sink, sizeof(sink), 0) <= 0) break;
  }
  // The connection ends here. httplib still owns the descriptor: in its place
  // goes an unconnected socket, on which the response httplib writes after
  // the handler, and its next read, fail at once; httplib then closes it.
  // (shutdown() alone would leave httplib reading whatever the client still
  // sends as the next request.)
  const int dead = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (dead < 0 || ::dup2(dead, wire.fd) < 0) ::shutdown(wire.fd, SHUT_RDWR);
  if (dead >= 0) ::close(dead);
  res.status = 101;
}

void Gateway::RunWebSocketSession(int fd, void* ssl, const HttpBinding& binding, const PathBindings& variables,
                                  BidiCall& call) {
  const Wire wire{fd, static_cast<SSL*>(ssl), options_.websocket_write_timeout};
  const pb::Message& request_type = Prototype(binding.method->input_type());
  const pb::Message& response_type = Prototype(binding.method->output_type());
  WebSocketReader reader(options_.max_request_bytes);
  bool binary = false;  // the latest request's encoding, which answers follow
  bool client_closed = false;
  size_t received = 0;
  auto idle_deadline = Clock::now() + options_.websocket_idle_timeout;
  constexpr size_t kMaxPendingWrites = 4;

  auto send = [&](WsOpcode opcode, std::string_view payload) {
    std::string frame;
    AppendWebSocketFrame(opcode, payload, &frame);
    return wire.Write(frame);
  };
  auto close = [&](uint16_t code, std::string_view reason) {
    (void)send(WsOpcode::kClose, WebSocketClosePayload(code, reason));
  };
  // A failed session: the status as the last message, then the close.
  auto fail = [&](const grpc::Status& status) {
    if (send(WsOpcode::kText, ErrorJson(status.error_code(), status.error_message())))
      close(static_cast<uint16_t>(kWsCloseStatusBase + status.error_code()), status.error_message());
  };
  // One request message from a frame; INVALID_ARGUMENT naming the message.
  auto decode = [&](const WsEvent& e, std::string* serialized) -> grpc::Status {
    const std::string where = "message " + std::to_string(received);
    std::unique_ptr<pb::Message> m(request_type.New());
    if (e.opcode == WsOpcode::kBinary) {
      if (!m->ParseFromString(e.payload))
        return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                            where + ": not a valid " + request_type.GetTypeName() + " encoding");
    } else if (auto st = JsonToMessage(e.payload, m.get(), where, where + " field"); !st.ok()) {
      return st;
    }
    if (received == 1) {  // the path's fields go with the first message
      HttpRequestParts parts;
      parts.path = variables;
      std::unique_ptr<pb::Message> params(request_type.New());
      if (auto st = ParamsMessage(binding, parts, params.get()); !st.ok()) return st;
      m->MergeFrom(*params);
    }
    *serialized = m->SerializeAsString();
    return grpc::Status::OK;
  };

  std::vector<char> buf(64 << 10);
  while (true) {
    // Answers first, as they come.
    std::string answer;
    BidiCall::Next next;
    while ((next = call.Read(&answer)) == BidiCall::Next::kMessage) {
      bool sent;
      if (binary) {
        sent = send(WsOpcode::kBinary, answer);
      } else {
        HttpBody body;
        const grpc::Status st =
            TranscodeResponse(binding, response_type, std::move(answer), options_.max_reply_bytes, &body);
        if (!st.ok()) return fail(st);
        sent = send(WsOpcode::kText, body.content);
      }
      if (!sent) return;
    }
    if (next == BidiCall::Next::kEnd) {
      const grpc::Status status = call.status();
      if (!status.ok()) return fail(status);
      return close(kWsCloseNormal, "");
    }
    // Then the client's frames, while the call has room for requests.
    bool more_events = true;
    while (!client_closed && call.pending_writes() < kMaxPendingWrites) {
      WsEvent e = reader.Next();
      if (e.kind == WsEvent::Kind::kNone) {
        more_events = false;
        break;
      }
      switch (e.kind) {
        case WsEvent::Kind::kMessage: {
          ++received;
          idle_deadline = Clock::now() + options_.websocket_idle_timeout;
          binary = e.opcode == WsOpcode::kBinary;
          std::string serialized;
          if (auto st = decode(e, &serialized); !st.ok()) return fail(st);
          (void)call.Write(std::move(serialized));  // refused once the call ended: its status follows
          break;
        }
        case WsEvent::Kind::kPing:
          if (!send(WsOpcode::kPong, e.payload)) return;
          break;
        case WsEvent::Kind::kPong: break;
        case WsEvent::Kind::kClose:
          // The client is done sending: half-close, answer what is left, then close.
          client_closed = true;
          call.WritesDone();
          idle_deadline = std::min(idle_deadline, Clock::now() + std::chrono::seconds(5));
          break;
        case WsEvent::Kind::kError: return close(e.close_code, e.payload);
        case WsEvent::Kind::kNone: break;
      }
    }
    const auto now = Clock::now();
    if (now >= idle_deadline) {
      call.Cancel();
      return close(kWsCloseGoingAway, "idle for " + std::to_string(options_.websocket_idle_timeout.count()) + " ms");
    }
    // Read from the socket only when the reader has no whole frame left.
    const bool want_socket = !client_closed && !more_events && call.pending_writes() < kMaxPendingWrites;
    if (want_socket && wire.Buffered()) {
      const ssize_t n = wire.Read(buf.data(), buf.size());
      if (n == Wire::kNothingYet) continue;
      if (n <= 0) return;
      reader.Feed(std::string_view(buf.data(), static_cast<size_t>(n)));
      continue;
    }
    pollfd fds[2] = {{call.wake_fd(), POLLIN, 0}, {fd, static_cast<short>(want_socket ? POLLIN : 0), 0}};
    const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(idle_deadline - now).count() + 1;
    if (::poll(fds, 2, static_cast<int>(std::min<int64_t>(wait, 60000))) < 0 && errno != EINTR) return;
    if (fds[0].revents) call.ClearWake();
    if (fds[1].revents & (POLLERR | POLLNVAL)) return;
    if (fds[1].revents & (POLLIN | POLLHUP)) {
      const ssize_t n = wire.Read(buf.data(), buf.size());
      if (n == Wire::kNothingYet) continue;  // part of a TLS record: the rest comes later
      if (n <= 0) return;  // the client went away: the call is cancelled
      reader.Feed(std::string_view(buf.data(), static_cast<size_t>(n)));
    }
  }
}

}  // namespace armature::server::gateway
