// Counts open sessions per client and in all, so a client cannot hold the
// server's memory with factorizations (RESOURCE_EXHAUSTED naming the limit).
#pragma once

#include <map>
#include <mutex>
#include <string>

#include <grpcpp/grpcpp.h>

#include "armature/engine/status.h"
#include "server/limits.h"

namespace armature::server {

class SessionLimiter {
 public:
  explicit SessionLimiter(const Limits& limits) : limits_(limits) {}

  // Takes a slot for `client`, or RESOURCE_EXHAUSTED naming
  // max_sessions_per_client / max_sessions. Each Ok needs one Release.
  Status Acquire(const std::string& client);
  void Release(const std::string& client);
  int open() const;

 private:
  const Limits& limits_;
  mutable std::mutex mu_;
  std::map<std::string, int> per_client_;
  int total_ = 0;
};

// Who a session belongs to: the bearer token when the call has one (one
// client behind several connections), else the peer's address without port.
std::string ClientKeyOf(const grpc::CallbackServerContext& context);

}  // namespace armature::server
