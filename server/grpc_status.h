// The one boundary between engine Status and gRPC status.
#pragma once

#include <grpcpp/grpcpp.h>

#include "armature/engine/status.h"

namespace armature::server {

grpc::Status ToGrpcStatus(const Status& status);

// Finishes a callback unary call with `status` (the thin-handler idiom).
grpc::ServerUnaryReactor* FinishUnary(grpc::CallbackServerContext* context, const Status& status);

}  // namespace armature::server
