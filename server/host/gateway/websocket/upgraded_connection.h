// The connection of a WebSocket upgrade, taken over from cpp-httplib 0.11
// (which knows nothing of WebSockets): found by its socket (the TLS session,
// or the descriptor whose two addresses are the request's), made
// non-blocking, and closed under httplib when the session ends.
//
// A read takes what has come and never waits (half a TLS record waits in
// OpenSSL for the rest), so the session's writes never wait on its reads; a
// write waits for room at most `write_timeout` in all.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string_view>

#include <openssl/ssl.h>

namespace httplib {
struct Request;
}

namespace armature::server::gateway {

class UpgradedConnection {
 public:
  static constexpr ssize_t kNothingYet = -2;

  // The request's connection, made non-blocking; nullopt when its socket is not found.
  static std::optional<UpgradedConnection> TakeOver(const httplib::Request& req,
                                                    std::chrono::milliseconds write_timeout);

  int fd() const { return fd_; }
  // Each frame goes out at once (no Nagle wait for the ACK of the previous one).
  void SendImmediately() const;
  // True when TLS holds decrypted bytes not read yet (poll() does not see them).
  bool Buffered() const { return ssl_ && SSL_pending(ssl_) > 0; }
  // >0 bytes read, kNothingYet, 0 the peer closed, -1 an error.
  ssize_t Read(char* buf, size_t n) const;
  bool Write(std::string_view data) const;
  // Ends the connection: a lingering close, then an unconnected socket in the
  // descriptor's place, so that httplib (which still owns it) fails at once.
  void Close() const;

 private:
  UpgradedConnection(int fd, SSL* ssl, std::chrono::milliseconds write_timeout)
      : fd_(fd), ssl_(ssl), write_timeout_(write_timeout) {}

  int fd_ = -1;
  SSL* ssl_ = nullptr;
  std::chrono::milliseconds write_timeout_{10000};
};

}  // namespace armature::server::gateway
