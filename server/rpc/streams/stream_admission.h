// Admission of streams (server-streaming and bidirectional calls: StreamClip,
// StreamSkinnedMesh, IkSession, DeformSession): one place per open stream,
// held by a Ticket until the call is done, at most --max-streams-per-client
// per client (the client as SessionAdmission sees it: its verified bearer
// token, else its address) and --max-streams in all. Over a limit:
// RESOURCE_EXHAUSTED naming the flag. Sessions also count against the
// session limits (session_admission.h).
#pragma once

#include <map>
#include <mutex>
#include <string>
#include <string_view>

#include <grpcpp/grpcpp.h>

#include "armature/base/status.h"
#include "server/rpc/streams/admission_ticket.h"
#include "server/rpc/limits.h"

namespace armature::server {

class StreamAdmission {
 public:
  // `tokens_verified`: an auth gate admits only accepted tokens, so a token
  // names its client (caller_identity.h).
  StreamAdmission(const Limits& limits, bool tokens_verified)
      : limit_(limits.max_streams_per_client), total_limit_(limits.max_streams), tokens_verified_(tokens_verified) {}
  StreamAdmission(const StreamAdmission&) = delete;
  StreamAdmission& operator=(const StreamAdmission&) = delete;

  // One open stream's place. The admission must outlive its tickets.
  using Ticket = AdmissionTicket;

  // A place for a stream of `rpc` (named in the refusal) for the caller of
  // `context`, or RESOURCE_EXHAUSTED naming --max-streams-per-client.
  StatusOr<Ticket> Admit(const grpc::ServerContextBase& context, std::string_view rpc);

  // Streams the client of `context` holds open now.
  int open(const grpc::ServerContextBase& context) const;

 private:
  void Release(const std::string& client);

  const int limit_;
  const int total_limit_;
  const bool tokens_verified_;
  mutable std::mutex mu_;
  std::map<std::string, int> per_client_;
  int total_ = 0;
};

}  // namespace armature::server
