// One gRPC call of any kind (unary, client, server or bidi streaming) through
// a channel with grpc::GenericStub: serialized messages in and out, so the
// gateway calls any method by name without generated stubs.
//
// On the wire every kind is a bidi stream: the call writes its requests,
// half-closes, and reads until the status. Responses wait in a small bounded
// queue for the one consumer thread (an HTTP handler), so a slow HTTP client
// slows the RPC down through gRPC flow control instead of piling up frames.
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>

namespace armature::server::gateway {

// A received message's bytes, the buffer emptied.
std::string TakeMessage(grpc::ByteBuffer* buffer);

class GenericCall {
 public:
  enum class Next { kMessage, kEnd, kTimeout };
  static constexpr std::chrono::milliseconds kForever = std::chrono::milliseconds::max();

  // Starts the call; `context` carries the deadline and metadata.
  static std::unique_ptr<GenericCall> Start(grpc::GenericStub& stub, const std::string& method,
                                            std::unique_ptr<grpc::ClientContext> context,
                                            std::vector<std::string> requests, size_t queue_capacity = 8);
  // Cancels the call if it is still running.
  ~GenericCall();

  // Waits up to `timeout` for the next response (kMessage, into `out`) or the
  // end of the call (kEnd; then status()). One consumer thread only.
  Next Read(std::string* out, std::chrono::milliseconds timeout = kForever);
  // Reads everything that is left; returns the final status.
  grpc::Status Drain(std::vector<std::string>* responses);
  grpc::Status status() const;  // OK until the call has ended

  // Cancels the call (the HTTP client went away, or shutdown). Idempotent;
  // unlike Read, any thread may call it.
  void Cancel();

 private:
  struct State;
  class Reactor;
  explicit GenericCall(std::shared_ptr<State> state) : state_(std::move(state)) {}
  void ResumeReading();

  std::shared_ptr<State> state_;  // shared with the reactor until its OnDone
};

}  // namespace armature::server::gateway
