// The gateway's calls in flight. The in-process transport drops its calls as
// soon as the gRPC server starts shutting down, so the gateway drains first:
// it refuses new calls, lets those in flight finish for the grace period and
// cancels what is left (endless streams among them).
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <set>

#include "server/host/gateway/common/bidi_call.h"
#include "server/host/gateway/common/generic_call.h"

namespace armature::server::gateway {

// UNAVAILABLE: the server is shutting down (the registry is draining).
grpc::Status ShuttingDown();

class CallRegistry {
 public:
  // Adds `call` (it must be removed before it is destroyed); false, adding
  // nothing, once draining has begun.
  bool Add(GenericCall* call);
  void Remove(GenericCall* call);
  bool Add(BidiCall* call);  // WebSocket sessions
  void Remove(BidiCall* call);

  bool draining() const;
  void BeginDrain();
  // Waits until no call is left or `deadline` passes, then cancels the rest
  // and waits for their handlers to let go of them.
  void Drain(std::chrono::system_clock::time_point deadline);

 private:
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::set<GenericCall*> calls_;
  std::set<BidiCall*> sessions_;
  bool draining_ = false;
};

}  // namespace armature::server::gateway
