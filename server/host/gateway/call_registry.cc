#include "server/host/gateway/call_registry.h"

namespace armature::server::gateway {

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
  cv_.wait_until(lock, deadline, [this] { return calls_.empty(); });
  for (GenericCall* call : calls_) call->Cancel();  // still registered, so still alive
  // Cancelled calls end promptly; their handlers then write and remove them.
  cv_.wait_for(lock, std::chrono::seconds(5), [this] { return calls_.empty(); });
}

}  // namespace armature::server::gateway
