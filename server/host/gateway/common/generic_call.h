// One gRPC call of any kind (unary, client, server or bidi streaming) through
// a channel with grpc::GenericStub: serialized messages in and out, so the
// gateway calls any method by name without generated stubs.
//
// On the wire every kind is a bidi stream: the call writes its requests
// (given at the start, or one by one with StartWriting), half-closes, and
// reads until the status. Responses wait in a small bounded
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
  // Starts a call whose requests come one by one (Write, then CloseWrites):
  // a client-streaming upload read from its HTTP body as it arrives, at most
  // `write_capacity` requests waiting for gRPC.
  static std::unique_ptr<GenericCall> StartWriting(grpc::GenericStub& stub, const std::string& method,
                                                   std::unique_ptr<grpc::ClientContext> context,
                                                   size_t write_capacity = 2);
  // Cancels the call if it is still running.
  ~GenericCall();

  // Queues the next request, waiting while write_capacity are queued; false
  // once the call is over (the server answered early, or it was cancelled):
  // then stop sending, CloseWrites and Drain for the status. The producer's
  // thread only.
  bool Write(std::string request);
  // No more requests: the call half-closes once the queued ones are sent.
  void CloseWrites();

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
