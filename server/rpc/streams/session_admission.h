// Admission of long-lived sessions (IK, deformation and playback): one place per open
// session, held by a Ticket until the session ends, so a reactor cannot leak
// one. Limits, each RESOURCE_EXHAUSTED naming its flag:
//   --max-sessions-per-client  every kind together, per client
//   --max-sessions             every kind together, all clients
//   --max-ik-sessions          IK sessions, all clients (0 turns them off)
// A client is its bearer token when an auth gate verified it, else its
// address without the port (REST and WebSocket clients: the HTTP client's
// address, which the gateway may take from a trusted proxy; caller_identity.h). Open sessions are the
// armature_sessions_active{kind} gauge.
#pragma once

#include <array>
#include <map>
#include <mutex>
#include <string>

#include <grpcpp/grpcpp.h>

#include "armature/base/status.h"
#include "server/rpc/streams/admission_ticket.h"
#include "server/rpc/streams/session_kind.h"
#include "server/rpc/caller_identity.h"
#include "server/rpc/limits.h"
#include "server/rpc/metrics.h"

namespace armature::server {

class SessionAdmission {
 public:
  // `tokens_verified`: an auth gate admits only accepted tokens, so a token
  // names its client (caller_identity.h).
  SessionAdmission(const Limits& limits, bool tokens_verified) : limits_(limits), tokens_verified_(tokens_verified) {}
  SessionAdmission(const SessionAdmission&) = delete;
  SessionAdmission& operator=(const SessionAdmission&) = delete;

  // One open session's place. The admission must outlive its tickets.
  using Ticket = AdmissionTicket;

  // A place for a `kind` session of the caller of `context`, or
  // RESOURCE_EXHAUSTED naming the limit it would go over.
  StatusOr<Ticket> Admit(const grpc::ServerContextBase& context, SessionKind kind);

  int open(SessionKind kind) const;

  // armature_sessions_active{kind="ik"|"deform"|"playback"}.
  void Collect(PrometheusText& out) const;

 private:
  void Release(const std::string& client, SessionKind kind);

  const Limits limits_;
  const bool tokens_verified_;
  mutable std::mutex mu_;
  std::map<std::string, int> per_client_;
  std::array<int, kSessionKindCount> per_kind_{};
  int total_ = 0;
};

}  // namespace armature::server
