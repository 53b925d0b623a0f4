// One bidirectional gRPC call through a channel with grpc::GenericStub, for a
// consumer that interleaves writes and reads (a WebSocket session): requests
// are written as they come, responses wait in a bounded queue, and an eventfd
// (wake_fd) becomes readable whenever something changed (a response came, a
// write finished, the call ended), so one thread can poll() the client's
// socket and the call together.
#pragma once

#include <memory>
#include <string>

#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>

namespace armature::server::gateway {

class BidiCall {
 public:
  enum class Next { kMessage, kEnd, kNone };

  // Starts the call; `context` carries the deadline and metadata. At most
  // `queue_capacity` responses wait unread (gRPC flow control does the rest).
  static std::unique_ptr<BidiCall> Start(grpc::GenericStub& stub, const std::string& method,
                                         std::unique_ptr<grpc::ClientContext> context, size_t queue_capacity = 8);
  // Cancels the call if it is still running.
  ~BidiCall();

  // Queues a request; false once the call takes no more (it ended, failed or
  // was half-closed). Bound the queue with pending_writes().
  bool Write(std::string message);
  size_t pending_writes() const;  // queued or in flight
  // Half-closes after the queued requests.
  void WritesDone();

  // Without waiting: the next response (kMessage), the end of the call
  // (kEnd, then status()), or nothing yet (kNone; poll wake_fd()).
  Next Read(std::string* out);
  grpc::Status status() const;  // OK until the call has ended

  // Readable when the call has news; the consumer drains it with ClearWake().
  int wake_fd() const;
  void ClearWake();

  // Cancels the call. Idempotent; any thread may call it.
  void Cancel();

 private:
  struct State;
  class Reactor;
  explicit BidiCall(std::shared_ptr<State> state) : state_(std::move(state)) {}
  void Pump();  // starts what the state asks for (a read, a write, the half-close)

  std::shared_ptr<State> state_;  // shared with the reactor until its OnDone
};

}  // namespace armature::server::gateway
