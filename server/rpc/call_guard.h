// The exception boundary where gRPC calls enter our code: unary handlers,
// handlers that create reactors, and reactor callbacks. Whatever escapes
// (an allocation failure deep in an import, a bug) becomes an answer —
// RESOURCE_EXHAUSTED for std::bad_alloc, INTERNAL otherwise, with a message —
// and an error log line carrying the request id, instead of a call that hangs
// until the client's deadline or comes back UNIMPLEMENTED with no message.
#pragma once

#include <exception>
#include <string>
#include <string_view>
#include <utility>

#include <grpcpp/grpcpp.h>

#include "armature/base/status.h"
#include "server/rpc/grpc_status.h"

namespace armature::server {

// The status for the exception being handled (call inside a catch block),
// logged with `where` (e.g. "EvaluateClip") and the call's request id.
Status StatusOfCurrentException(const grpc::ServerContextBase* context, std::string_view where) noexcept;

// The client's x-request-id when it sent a printable one, else "-".
std::string RequestIdOf(const grpc::ServerContextBase& context);

// Runs `fn` (returning Status); an exception becomes its status.
template <class Fn>
Status Guarded(const grpc::ServerContextBase* context, std::string_view where, Fn&& fn) noexcept {
  try {
    return std::forward<Fn>(fn)();
  } catch (...) {
    return StatusOfCurrentException(context, where);
  }
}

// A unary handler's body: `fn` fills the response and returns the status.
template <class Fn>
grpc::ServerUnaryReactor* RunUnary(grpc::CallbackServerContext* context, std::string_view where, Fn&& fn) noexcept {
  return FinishUnary(context, Guarded(context, where, std::forward<Fn>(fn)));
}

// A reactor callback's body: `fn` runs; if it throws, `finish` gets the
// status to end the call with (it must call Finish once, and not throw).
template <class Fn, class Finish>
void GuardCallback(const grpc::ServerContextBase* context, std::string_view where, Fn&& fn, Finish&& finish) noexcept {
  Status failed;
  try {
    std::forward<Fn>(fn)();
    return;
  } catch (...) {
    failed = StatusOfCurrentException(context, where);
  }
  std::forward<Finish>(finish)(ToGrpcStatus(failed));
}

// A reactor that only finishes with `status` (a handler that threw before it made its own).
template <class Base>
class FinishedReactor final : public Base {
 public:
  explicit FinishedReactor(const Status& status) { this->Finish(ToGrpcStatus(status)); }
  void OnDone() override { delete this; }
};

// A streaming handler's body: `make` returns the reactor; if it throws, the
// call gets a reactor that finishes with the exception's status.
template <class Reactor, class Fn>
Reactor* MakeReactor(const grpc::ServerContextBase* context, std::string_view where, Fn&& make) noexcept {
  try {
    return std::forward<Fn>(make)();
  } catch (...) {
    const Status status = StatusOfCurrentException(context, where);
    try {
      return new FinishedReactor<Reactor>(status);
    } catch (...) {
      return nullptr;  // out of memory even for that: gRPC answers UNIMPLEMENTED
    }
  }
}

}  // namespace armature::server
