#include "server/rpc/streams/stream_admission.h"

#include "server/rpc/streams/session_admission.h"

namespace armature::server {

StatusOr<StreamAdmission::Ticket> StreamAdmission::Admit(const grpc::ServerContextBase& context, std::string_view rpc) {
  std::string client = ClientIdentityOf(context, tokens_verified_);
  {
    std::lock_guard lock(mu_);
    if (total_ >= total_limit_)
      return Status::ResourceExhausted(std::string(rpc) + ": " + std::to_string(total_) +
                                       " streams are open on this server, the limit --max-streams (" +
                                       std::to_string(total_limit_) + "); retry later");
    auto it = per_client_.find(client);
    const int held = it == per_client_.end() ? 0 : it->second;
    if (held >= limit_)
      return Status::ResourceExhausted(std::string(rpc) + ": this client already has " + std::to_string(held) +
                                       " streams open, the limit --max-streams-per-client (" + std::to_string(limit_) +
                                       "); close one and retry");
    ++per_client_[client];
    ++total_;
  }
  return Ticket([this, client = std::move(client)] { Release(client); });
}

int StreamAdmission::open(const grpc::ServerContextBase& context) const {
  std::lock_guard lock(mu_);
  auto it = per_client_.find(ClientIdentityOf(context, tokens_verified_));
  return it == per_client_.end() ? 0 : it->second;
}

void StreamAdmission::Release(const std::string& client) {
  std::lock_guard lock(mu_);
  auto it = per_client_.find(client);
  if (it != per_client_.end() && --it->second <= 0) per_client_.erase(it);
  --total_;
}

}  // namespace armature::server
