#include "server/host/gateway/websocket/upgraded_connection.h"

#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <httplib.h>

namespace armature::server::gateway {
namespace {

using Clock = std::chrono::steady_clock;

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

}  // namespace

std::optional<UpgradedConnection> UpgradedConnection::TakeOver(const httplib::Request& req,
                                                               std::chrono::milliseconds write_timeout) {
  SSL* ssl = req.ssl ? const_cast<SSL*>(req.ssl) : nullptr;
  const int fd = ssl ? SSL_get_fd(ssl) : FindConnectionFd(req);
  if (fd < 0) return std::nullopt;
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
  return UpgradedConnection(fd, ssl, write_timeout);
}

void UpgradedConnection::SendImmediately() const {
  const int one = 1;
  ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
}

ssize_t UpgradedConnection::Read(char* buf, size_t n) const {
  if (!ssl_) {
    const ssize_t r = ::recv(fd_, buf, n, 0);
    return r >= 0 ? r : (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) ? kNothingYet : -1;
  }
  const int r = SSL_read(ssl_, buf, static_cast<int>(std::min<size_t>(n, 1 << 30)));
  if (r > 0) return r;
  switch (SSL_get_error(ssl_, r)) {
    case SSL_ERROR_ZERO_RETURN: return 0;
    case SSL_ERROR_WANT_READ:
    case SSL_ERROR_WANT_WRITE: return kNothingYet;
    default: return -1;
  }
}

bool UpgradedConnection::Write(std::string_view data) const {
  const auto deadline = Clock::now() + write_timeout_;
  while (!data.empty()) {
    short want = POLLOUT;
    if (ssl_) {
      const int w = SSL_write(ssl_, data.data(), static_cast<int>(std::min<size_t>(data.size(), 1 << 30)));
      if (w > 0) {
        data.remove_prefix(static_cast<size_t>(w));
        continue;
      }
      const int e = SSL_get_error(ssl_, w);
      if (e != SSL_ERROR_WANT_WRITE && e != SSL_ERROR_WANT_READ) return false;
      if (e == SSL_ERROR_WANT_READ) want = POLLIN;
    } else {
      const ssize_t w = ::send(fd_, data.data(), data.size(), MSG_NOSIGNAL);
      if (w >= 0) {
        data.remove_prefix(static_cast<size_t>(w));
        continue;
      }
      if (errno == EINTR) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK) return false;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    pollfd p{fd_, want, 0};
    if (left <= 0 || ::poll(&p, 1, static_cast<int>(left)) <= 0) return false;
  }
  return true;
}

void UpgradedConnection::Close() const {
  // Lingering close: our FIN after the close frame, then what the client still
  // sends is read and dropped until it closes too (or 2 s pass), so that no
  // reset destroys the close frame before the client has read it.
  ::shutdown(fd_, SHUT_WR);
  const auto linger_until = Clock::now() + std::chrono::seconds(2);
  for (char sink[16384];;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(linger_until - Clock::now()).count();
    pollfd p{fd_, POLLIN, 0};
    if (left <= 0 || ::poll(&p, 1, static_cast<int>(left)) <= 0 || ::recv(fd_, sink, sizeof(sink), 0) <= 0) break;
  }
  // The connection ends here. httplib still owns the descriptor: in its place
  // goes an unconnected socket, on which the response httplib writes after
  // the handler, and its next read, fail at once; httplib then closes it.
  // (shutdown() alone would leave httplib reading whatever the client still
  // sends as the next request.)
  const int dead = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (dead < 0 || ::dup2(dead, fd_) < 0) ::shutdown(fd_, SHUT_RDWR);
  if (dead >= 0) ::close(dead);
}

}  // namespace armature::server::gateway
