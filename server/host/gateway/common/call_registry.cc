#include "server/host/gateway/common/call_registry.h"

namespace armature::server::gateway {

grpc::Status ShuttingDown() { return grpc::Status(grpc::StatusCode::UNAVAILABLE, "the server is shutting down"); }

bool CallRegistry::Add(GenericCall* call) {
  std::lock_guard lock(mu_);
  if (draining_) return false;
  calls_.insert(call);
  return true;
}

void CallRegistry::Remove(GenericCall* call) {
  std::lock_guard lock(mu_);
  calls_.erase(call);
  cv_.notify_all();
}

bool CallRegistry::Add(BidiCall* call) {
  std::lock_guard lock(mu_);
  if (draining_) return false;
  sessions_.insert(call);
  return true;
}

void CallRegistry::Remove(BidiCall* call) {
  std::lock_guard lock(mu_);
  sessions_.erase(call);
  cv_.notify_all();
}

bool CallRegistry::draining() const {
  std::lock_guard lock(mu_);
  return draining_;
}

void CallRegistry::BeginDrain() {
  std::lock_guard lock(mu_);
  draining_ = true;
}

void CallRegistry::Drain(std::chrono::system_clock::time_point deadline) {
  std::unique_lock lock(mu_);
  draining_ = true;
  const auto none = [this] { return calls_.empty() && sessions_.empty(); };
  cv_.wait_until(lock, deadline, none);
  for (GenericCall* call : calls_) call->Cancel();  // still registered, so still alive
  for (BidiCall* call : sessions_) call->Cancel();
  // Cancelled calls end promptly; their handlers then write and remove them.
  cv_.wait_for(lock, std::chrono::seconds(5), none);
}

}  // namespace armature::server::gateway
