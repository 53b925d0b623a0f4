// One connection on the HTTP port, served by cpp-httplib's request parser
// on a stream of our own, so that the whole request head (TLS handshake,
// request line and headers) has one deadline instead of httplib's per-read
// timeout, which a client sending a byte every few seconds never reaches,
// and so that each client address holds a bounded number of connections.
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "server/host/gateway/common/forwarded_for.h"

namespace httplib {
class Server;
}

namespace armature::server {

struct HttpConnectionLimits {
  std::chrono::milliseconds head_timeout{10000};  // --http-head-timeout
  int max_per_address = 64;                       // --http-max-connections-per-address
  gateway::TrustedProxies trusted_proxies;        // not capped: a proxy carries many clients
};

// Open connections per client address, each held by a slot until it closes.
class ConnectionsPerAddress {
 public:
  explicit ConnectionsPerAddress(int limit) : limit_(limit) {}
  int limit() const { return limit_; }
  // True, and one place taken, when `address` has fewer than the limit open.
  bool TryTake(const std::string& address);
  void Release(const std::string& address);

 private:
  const int limit_;
  std::mutex mu_;
  std::map<std::string, int> open_;
};

// httplib listens with a backlog of 5: a burst of connects beyond it is
// ended by the kernel before the server sees it. Call after binding.
void WidenListenBacklog(httplib::Server& server);

// An httplib server, TLS when `cert` is set (SSLServer), whose connections
// are served under `limits`.
std::unique_ptr<httplib::Server> MakeGuardedHttpServer(const HttpConnectionLimits& limits, const std::string& cert,
                                                       const std::string& key);

}  // namespace armature::server
