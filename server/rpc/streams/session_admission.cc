#include "server/rpc/streams/session_admission.h"

namespace armature::server {

namespace {

const char* RpcOf(SessionKind kind) {
  switch (kind) {
    case SessionKind::kIk: return "IkSession";
    case SessionKind::kDeform: return "DeformSession";
    case SessionKind::kPlayback: return "PlaybackSession";
    case SessionKind::kCrowd: return "CrowdSession";
  }
  return "?";
}
const char* LabelOf(SessionKind kind) {
  switch (kind) {
    case SessionKind::kIk: return "ik";
    case SessionKind::kDeform: return "deform";
    case SessionKind::kPlayback: return "playback";
    case SessionKind::kCrowd: return "crowd";
  }
  return "?";
}
int IndexOf(SessionKind kind) { return static_cast<int>(kind); }

Status Refused(SessionKind kind, const std::string& what, const char* flag, int limit, const char* advice) {
  return Status::ResourceExhausted(std::string(RpcOf(kind)) + ": " + what + ", the limit " + flag + " (" +
                                   std::to_string(limit) + "); " + advice);
}

}  // namespace

StatusOr<SessionAdmission::Ticket> SessionAdmission::Admit(const grpc::ServerContextBase& context, SessionKind kind) {
  std::string client = ClientIdentityOf(context, tokens_verified_);
  {
    std::lock_guard lock(mu_);
    int& of_kind = per_kind_[IndexOf(kind)];
    if (kind == SessionKind::kIk && of_kind >= limits_.max_ik_sessions) {
      if (limits_.max_ik_sessions == 0)
        return Refused(kind, "IK sessions are turned off on this server", "--max-ik-sessions", 0, "use SolveIk");
      return Refused(kind, std::to_string(of_kind) + " IK sessions are open on this server", "--max-ik-sessions",
                     limits_.max_ik_sessions, "close one and retry");
    }
    if (total_ >= limits_.max_sessions)
      return Refused(kind, std::to_string(total_) + " sessions (IK, deformation and playback) are open on this server",
                     "--max-sessions", limits_.max_sessions, "close one or retry later");
    int& mine = per_client_[client];
    if (mine >= limits_.max_sessions_per_client) {
      const int held = mine;
      if (held == 0) per_client_.erase(client);
      return Refused(
          kind, "this client already has " + std::to_string(held) + " sessions (IK, deformation and playback) open",
          "--max-sessions-per-client", limits_.max_sessions_per_client, "close one and retry");
    }
    ++mine;
    ++of_kind;
    ++total_;
  }
  return Ticket([this, client = std::move(client), kind] { Release(client, kind); });
}

void SessionAdmission::Release(const std::string& client, SessionKind kind) {
  std::lock_guard lock(mu_);
  auto it = per_client_.find(client);
  if (it != per_client_.end() && --it->second <= 0) per_client_.erase(it);
  --per_kind_[IndexOf(kind)];
  --total_;
}

int SessionAdmission::open(SessionKind kind) const {
  std::lock_guard lock(mu_);
  return per_kind_[IndexOf(kind)];
}

void SessionAdmission::Collect(PrometheusText& out) const {
  out.Family("armature_sessions_active", "gauge", "IK, deformation, playback and crowd sessions now open, by kind.");
  for (SessionKind kind : {SessionKind::kIk, SessionKind::kDeform, SessionKind::kPlayback, SessionKind::kCrowd})
    out.Sample("armature_sessions_active", {{"kind", LabelOf(kind)}}, static_cast<double>(open(kind)));
}

}  // namespace armature::server
