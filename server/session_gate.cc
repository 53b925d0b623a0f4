#include "server/session_gate.h"

#include "server/auth_gate.h"

namespace armature::server {
namespace {

// "token:<authorization>" or "peer:<address>" ("ipv4:10.0.0.7:51234" → "peer:ipv4:10.0.0.7").
std::string ClientOf(const grpc::ServerContextBase& context) {
  if (std::string auth = AuthorizationOf(context); !auth.empty()) return "token:" + auth;
  std::string peer = context.peer();
  const size_t colon = peer.rfind(':');
  if (colon != std::string::npos && colon > peer.find(':')) peer.resize(colon);
  return "peer:" + peer;
}

}  // namespace

StatusOr<SessionGate::Ticket> SessionGate::Admit(const grpc::ServerContextBase& context) {
  std::string client = ClientOf(context);
  {
    std::lock_guard lock(mu_);
    int& open = open_[client];
    if (open >= max_per_client_) {
      if (open == 0) open_.erase(client);
      return Status::ResourceExhausted("sessions: this client already has " + std::to_string(max_per_client_) +
                                       " open, the limit (--max-sessions-per-client); close one and retry");
    }
    ++open;
  }
  open_gauge_.fetch_add(1, std::memory_order_relaxed);
  Ticket ticket;
  ticket.gate_ = this;
  ticket.client_ = std::move(client);
  return ticket;
}

SessionGate::Ticket& SessionGate::Ticket::operator=(Ticket&& other) noexcept {
  if (this != &other) {
    Release();
    gate_ = other.gate_;
    client_ = std::move(other.client_);
    other.gate_ = nullptr;
  }
  return *this;
}

void SessionGate::Ticket::Release() {
  if (!gate_) return;
  {
    std::lock_guard lock(gate_->mu_);
    auto it = gate_->open_.find(client_);
    if (it != gate_->open_.end() && --it->second <= 0) gate_->open_.erase(it);
  }
  gate_->open_gauge_.fetch_sub(1, std::memory_order_relaxed);
  gate_ = nullptr;
}

}  // namespace armature::server
