#include "server/session_limiter.h"

namespace armature::server {

Status SessionLimiter::Acquire(const std::string& client) {
  std::lock_guard lock(mu_);
  if (total_ >= limits_.max_sessions)
    return Status::ResourceExhausted("max_sessions (" + std::to_string(limits_.max_sessions) +
                                     ") sessions are open on this server; close one or retry later");
  int& mine = per_client_[client];
  if (mine >= limits_.max_sessions_per_client)
    return Status::ResourceExhausted("max_sessions_per_client (" + std::to_string(limits_.max_sessions_per_client) +
                                     ") sessions are already open for this client");
  ++mine;
  ++total_;
  return Status::Ok();
}

void SessionLimiter::Release(const std::string& client) {
  std::lock_guard lock(mu_);
  auto it = per_client_.find(client);
  if (it == per_client_.end()) return;
  if (--it->second == 0) per_client_.erase(it);
  --total_;
}

int SessionLimiter::open() const {
  std::lock_guard lock(mu_);
  return total_;
}

std::string ClientKeyOf(const grpc::CallbackServerContext& context) {
  const auto& metadata = context.client_metadata();
  if (auto it = metadata.find("authorization"); it != metadata.end())
    return "token:" + std::string(it->second.data(), it->second.size());
  std::string peer = context.peer();  // "ipv4:127.0.0.1:5555", "ipv6:[::1]:5555", "unix:…"
  if (auto colon = peer.rfind(':'); colon != std::string::npos && peer.rfind("unix:", 0) != 0) peer.resize(colon);
  return "peer:" + peer;
}

}  // namespace armature::server
