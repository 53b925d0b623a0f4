#include "server/host/http/connection_stream.h"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstring>

#include <openssl/ssl.h>

namespace armature::server {
namespace {

constexpr char kHeadEnd[] = "\r\n\r\n";

// What a failed TLS call waits for: POLLIN, POLLOUT, or 0 when it failed for good.
short TlsWant(SSL* ssl, int result) {
  switch (SSL_get_error(ssl, result)) {
    case SSL_ERROR_WANT_READ: return POLLIN;
    case SSL_ERROR_WANT_WRITE: return POLLOUT;
    default: return 0;
  }
}

// The same for a failed recv/send.
short SocketWant(short events) {
  if (errno == EAGAIN || errno == EWOULDBLOCK) return events;
  return errno == EINTR ? short{-1} : short{0};
}

void IpAndPort(const sockaddr_storage& addr, socklen_t len, std::string& ip, int& port) {
  char host[NI_MAXHOST];
  if (getnameinfo(reinterpret_cast<const sockaddr*>(&addr), len, host, sizeof(host), nullptr, 0, NI_NUMERICHOST) == 0)
    ip = host;
  if (addr.ss_family == AF_INET) port = ntohs(reinterpret_cast<const sockaddr_in&>(addr).sin_port);
  if (addr.ss_family == AF_INET6) port = ntohs(reinterpret_cast<const sockaddr_in6&>(addr).sin6_port);
}

}  // namespace

void ConnectionStream::ExpectHead(Clock::time_point deadline) {
  in_head_ = true;
  head_deadline_ = deadline;
  head_bytes_ = 0;
  head_end_matched_ = 0;
}

bool ConnectionStream::HeadTimedOut() const { return in_head_ && head_bytes_ > 0 && Clock::now() >= head_deadline_; }

bool ConnectionStream::Wait(short events, std::chrono::milliseconds timeout) const {
  // Rounded up, so a wait cut by the deadline ends at or after it, never just before.
  if (in_head_)
    timeout = std::min(timeout, std::chrono::ceil<std::chrono::milliseconds>(head_deadline_ - Clock::now()));
  if (timeout.count() <= 0) return false;
  pollfd p{fd_, events, 0};
  const int r = ::poll(&p, 1, static_cast<int>(std::min<int64_t>(timeout.count(), INT_MAX)));
  return r > 0 && (p.revents & (events | POLLHUP | POLLERR));
}

bool ConnectionStream::AcceptTls() {
  for (;;) {
    const int r = SSL_accept(ssl_);
    if (r == 1) return true;
    const short want = TlsWant(ssl_, r);
    if (want == 0 || !Wait(want, read_timeout_)) return false;
  }
}

bool ConnectionStream::WaitForRequest(std::chrono::milliseconds timeout) const {
  if (begin_ < end_ || (ssl_ && SSL_pending(ssl_) > 0)) return true;
  pollfd p{fd_, POLLIN, 0};
  return ::poll(&p, 1, static_cast<int>(timeout.count())) > 0;
}

bool ConnectionStream::is_readable() const {
  return WaitForRequest(in_head_ ? std::min(read_timeout_, std::chrono::duration_cast<std::chrono::milliseconds>(
                                                               head_deadline_ - Clock::now()))
                                 : read_timeout_);
}

bool ConnectionStream::is_writable() const {
  pollfd p{fd_, POLLOUT, 0};
  return ::poll(&p, 1, static_cast<int>(write_timeout_.count())) > 0 && (p.revents & POLLOUT);
}

ssize_t ConnectionStream::ReadSome(char* ptr, size_t size) {
  for (;;) {
    short want;
    if (ssl_) {
      const int r = SSL_read(ssl_, ptr, static_cast<int>(std::min<size_t>(size, INT_MAX)));
      if (r > 0) return r;
      if (SSL_get_error(ssl_, r) == SSL_ERROR_ZERO_RETURN) return 0;
      want = TlsWant(ssl_, r);
    } else {
      const ssize_t r = ::recv(fd_, ptr, size, 0);
      if (r >= 0) return r;
      want = SocketWant(POLLIN);
    }
    if (want < 0) continue;
    if (want == 0 || !Wait(want, read_timeout_)) return -1;
  }
}

void ConnectionStream::Note(const char* p, size_t n) {
  if (!in_head_) return;
  head_bytes_ += n;
  for (size_t i = 0; i < n && in_head_; ++i) {
    if (p[i] == kHeadEnd[head_end_matched_])
      ++head_end_matched_;
    else
      head_end_matched_ = p[i] == '\r' ? 1 : 0;
    if (head_end_matched_ == 4) in_head_ = false;
  }
}

ssize_t ConnectionStream::read(char* ptr, size_t size) {
  if (begin_ == end_) {
    // A large read past the head (a body) goes straight to the caller.
    if (!in_head_ && size >= sizeof(buffer_)) return ReadSome(ptr, size);
    const ssize_t n = ReadSome(buffer_, sizeof(buffer_));
    if (n <= 0) return n;
    begin_ = 0;
    end_ = static_cast<size_t>(n);
  }
  const size_t n = std::min(size, end_ - begin_);
  std::memcpy(ptr, buffer_ + begin_, n);
  begin_ += n;
  Note(ptr, n);
  return static_cast<ssize_t>(n);
}

ssize_t ConnectionStream::write(const char* ptr, size_t size) {
  for (;;) {
    short want;
    if (ssl_) {
      const int r = SSL_write(ssl_, ptr, static_cast<int>(std::min<size_t>(size, INT_MAX)));
      if (r > 0) return r;
      want = TlsWant(ssl_, r);
    } else {
      const ssize_t r = ::send(fd_, ptr, size, MSG_NOSIGNAL);
      if (r >= 0) return r;
      want = SocketWant(POLLOUT);
    }
    if (want < 0) continue;
    // Not cut by a head's deadline: an answer (a 100 Continue, an error) may go out during one.
    pollfd p{fd_, want, 0};
    if (want == 0 || ::poll(&p, 1, static_cast<int>(write_timeout_.count())) <= 0) return -1;
  }
}

void ConnectionStream::get_remote_ip_and_port(std::string& ip, int& port) const {
  sockaddr_storage addr{};
  socklen_t len = sizeof(addr);
  if (::getpeername(fd_, reinterpret_cast<sockaddr*>(&addr), &len) == 0) IpAndPort(addr, len, ip, port);
}

void ConnectionStream::get_local_ip_and_port(std::string& ip, int& port) const {
  sockaddr_storage addr{};
  socklen_t len = sizeof(addr);
  if (::getsockname(fd_, reinterpret_cast<sockaddr*>(&addr), &len) == 0) IpAndPort(addr, len, ip, port);
}

}  // namespace armature::server
