// Admission of long-lived sessions (IK sessions; deformation sessions
// later): at most --max-sessions-per-client open per client, counted
// across every kind, and the armature_sessions_active gauge. A client is
// its bearer token when it sends one, else its address without the port
// (so calls through the REST gateway, which arrive in-process, count as one
// client unless they carry tokens).
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>

#include <grpcpp/grpcpp.h>

#include "armature/engine/status.h"

namespace armature::server {

class SessionGate {
 public:
  // `open_gauge` (Metrics::sessions()) must outlive the gate.
  SessionGate(int max_per_client, std::atomic<int64_t>& open_gauge)
      : max_per_client_(max_per_client), open_gauge_(open_gauge) {}

  // Holds one place until destroyed.
  class Ticket {
   public:
    Ticket() = default;
    Ticket(Ticket&& other) noexcept { *this = std::move(other); }
    Ticket& operator=(Ticket&& other) noexcept;
    ~Ticket() { Release(); }

   private:
    friend class SessionGate;
    void Release();
    SessionGate* gate_ = nullptr;
    std::string client_;
  };

  // A place for the caller of `context`, or RESOURCE_EXHAUSTED naming
  // --max-sessions-per-client when it already holds that many.
  StatusOr<Ticket> Admit(const grpc::ServerContextBase& context);

 private:
  const int max_per_client_;
  std::atomic<int64_t>& open_gauge_;
  std::mutex mu_;
  std::map<std::string, int> open_;  // per client
};

}  // namespace armature::server
