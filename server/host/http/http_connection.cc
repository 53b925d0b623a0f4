#include "server/host/http/http_connection.h"

#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <type_traits>

#include <httplib.h>
#include <openssl/ssl.h>
#include <spdlog/fmt/fmt.h>

#include "server/host/http/connection_stream.h"
#include "server/host/gateway/common/error_mapping.h"

namespace armature::server {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

std::string PeerAddress(int fd) {
  sockaddr_storage addr{};
  socklen_t len = sizeof(addr);
  char host[NI_MAXHOST] = "";
  if (::getpeername(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0 ||
      getnameinfo(reinterpret_cast<sockaddr*>(&addr), len, host, sizeof(host), nullptr, 0, NI_NUMERICHOST) != 0)
    return "";
  return host;
}

milliseconds Ms(time_t sec, time_t usec) { return milliseconds(sec * 1000 + usec / 1000); }

// A whole response on a connection about to close (best effort: the client may be gone).
void Answer(httplib::Stream& stream, const char* status_line, grpc::StatusCode code, const std::string& message) {
  const std::string body = gateway::ErrorJson(code, message) + "\n";
  const std::string response =
      std::string("HTTP/1.1 ") + status_line +
      "\r\nContent-Type: application/json\r\nConnection: close\r\nContent-Length: " + std::to_string(body.size()) +
      "\r\n\r\n" + body;
  for (size_t sent = 0; sent < response.size();) {
    const ssize_t n = stream.write(response.data() + sent, response.size() - sent);
    if (n <= 0) return;
    sent += static_cast<size_t>(n);
  }
}

// Closes without a reset: bytes the client sent that were never read would
// make the kernel reset the connection, and the reset can destroy the
// answer before the client has read it. With `linger`, what the client
// still sends is read and dropped for that long (or until it closes too).
void CloseQuietly(int fd, milliseconds linger = milliseconds(0)) {
  for (char sink[4096]; ::recv(fd, sink, sizeof(sink), MSG_DONTWAIT) > 0;) {}
  if (linger.count() > 0) {
    ::shutdown(fd, SHUT_WR);
    const auto until = Clock::now() + linger;
    for (char sink[4096];;) {
      const auto left = std::chrono::duration_cast<milliseconds>(until - Clock::now()).count();
      pollfd p{fd, POLLIN, 0};
      if (left <= 0 || ::poll(&p, 1, static_cast<int>(left)) <= 0 || ::recv(fd, sink, sizeof(sink), 0) <= 0) break;
    }
  }
  ::shutdown(fd, SHUT_RDWR);
  ::close(fd);
}

// A slow client that was just told its head took too long is likely still
// sending: its answer needs a lingering close (a bounded one).
constexpr milliseconds kLingerAfterTimeout{1000};

template <class Base>
class GuardedHttpServer final : public Base {
 public:
  template <class... Args>
  explicit GuardedHttpServer(const HttpConnectionLimits& limits, Args&&... args)
      : Base(std::forward<Args>(args)...), limits_(limits), per_address_(limits.max_per_address) {}

 private:
  static constexpr bool kTls = std::is_same_v<Base, httplib::SSLServer>;

  // httplib's accept loop hands each accepted connection here, on a worker thread.
  bool process_and_close_socket(socket_t sock) override {
    const auto accepted = Clock::now();
    ::fcntl(sock, F_SETFL, ::fcntl(sock, F_GETFL) | O_NONBLOCK);
    SSL* ssl = nullptr;
    if constexpr (kTls) {
      ssl = SSL_new(this->ssl_context());
      if (ssl) SSL_set_fd(ssl, sock);
    }
    ConnectionStream stream(sock, ssl, Ms(this->read_timeout_sec_, this->read_timeout_usec_),
                            Ms(this->write_timeout_sec_, this->write_timeout_usec_));
    stream.ExpectHead(accepted + limits_.head_timeout);
    const std::string address = PeerAddress(sock);
    bool served = false, timed_out = false;
    const bool capped = !limits_.trusted_proxies.Contains(address);
    if (!capped || per_address_.TryTake(address)) {
      if (!kTls || (ssl && stream.AcceptTls())) served = ServeRequests(stream, ssl, &timed_out);
      if (capped) per_address_.Release(address);
    } else if (!kTls) {  // over TLS no answer is possible without a handshake, which the refusal must not wait for
      Answer(stream, "429 Too Many Requests", grpc::StatusCode::RESOURCE_EXHAUSTED,
             "too many connections from " + address + ": the limit --http-max-connections-per-address (" +
                 std::to_string(per_address_.limit()) + "); close one and retry");
    }
    if (ssl) {
      if (served) SSL_shutdown(ssl);
      SSL_free(ssl);
    }
    CloseQuietly(sock, timed_out ? kLingerAfterTimeout : milliseconds(0));
    return served;
  }

  // httplib's keep-alive loop, each request's head under the deadline.
  // `timed_out`: set when a head ran past its deadline and was answered 408.
  bool ServeRequests(ConnectionStream& stream, SSL* ssl, bool* timed_out) {
    const auto keep_alive = milliseconds(this->keep_alive_timeout_sec_ * 1000);
    bool ok = false;
    for (size_t left = this->keep_alive_max_count_; left > 0 && this->svr_sock_ != INVALID_SOCKET; --left) {
      if (left != this->keep_alive_max_count_) {
        if (!stream.WaitForRequest(keep_alive)) break;
        stream.ExpectHead(Clock::now() + limits_.head_timeout);
      }
      bool connection_closed = false;
      ok = this->process_request(stream, left == 1, connection_closed, [ssl](httplib::Request& req) { req.ssl = ssl; });
      // A head never finished: httplib answered 400 when the headers were cut
      // short, nothing when the request line was; the connection ends either way.
      if (!stream.HeadDone()) {
        *timed_out = !ok && stream.HeadTimedOut();
        if (*timed_out)
          Answer(
              stream, "408 Request Timeout", grpc::StatusCode::DEADLINE_EXCEEDED,
              fmt::format("the request head (request line and headers) took longer than --http-head-timeout ({:g} s)",
                          static_cast<double>(limits_.head_timeout.count()) / 1000));
        return false;
      }
      if (!ok || connection_closed) break;
    }
    return ok;
  }

  const HttpConnectionLimits limits_;
  ConnectionsPerAddress per_address_;
};

}  // namespace

bool ConnectionsPerAddress::TryTake(const std::string& address) {
  std::lock_guard lock(mu_);
  int& open = open_[address];
  if (open >= limit_) return false;
  ++open;
  return true;
}

void ConnectionsPerAddress::Release(const std::string& address) {
  std::lock_guard lock(mu_);
  auto it = open_.find(address);
  if (it != open_.end() && --it->second <= 0) open_.erase(it);
}

void WidenListenBacklog(httplib::Server& server) {
  // The protected listening socket, through a member pointer named via a derived class.
  struct Access : httplib::Server {
    static socket_t Of(httplib::Server& s) { return (s.*&Access::svr_sock_).load(); }
  };
  const socket_t sock = Access::Of(server);
  if (sock != INVALID_SOCKET) ::listen(sock, SOMAXCONN);  // on a listening socket: a new backlog
}

std::unique_ptr<httplib::Server> MakeGuardedHttpServer(const HttpConnectionLimits& limits, const std::string& cert,
                                                       const std::string& key) {
  if (cert.empty()) return std::make_unique<GuardedHttpServer<httplib::Server>>(limits);
  return std::make_unique<GuardedHttpServer<httplib::SSLServer>>(limits, cert.c_str(), key.c_str());
}

}  // namespace armature::server
