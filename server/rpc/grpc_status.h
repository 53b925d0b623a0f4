// The one boundary between engine Status and gRPC status.
#pragma once

#include <chrono>
#include <optional>

#include <grpcpp/grpcpp.h>

#include "armature/base/status.h"
#include "server/rpc/call_stop.h"

namespace armature::server {

grpc::Status ToGrpcStatus(const Status& status);

// "OK", "INVALID_ARGUMENT", … (metric labels, logs).
const char* GrpcCodeName(grpc::StatusCode code);

// Finishes a callback unary call with `status` (the thin-handler idiom).
grpc::ServerUnaryReactor* FinishUnary(grpc::CallbackServerContext* context, const Status& status);

// The call's deadline on the steady clock the engine checks (IkRequest.deadline), or none.
std::optional<std::chrono::steady_clock::time_point> SteadyDeadline(const grpc::ServerContextBase& context);

// The call's deadline and cancellation for work that knows no gRPC; `context` must outlive it.
CallStop CallStopOf(const grpc::ServerContextBase& context);

}  // namespace armature::server
