// When a call's work must stop, without gRPC: the call's deadline and the
// client's cancellation, as the IK solver and session logic check them. The
// adapters and the session reactor fill it from the gRPC context
// (CallStopOf, grpc_status.h).
#pragma once

#include <chrono>
#include <functional>
#include <optional>

namespace armature::server {

struct CallStop {
  std::optional<std::chrono::steady_clock::time_point> deadline;
  std::function<bool()> cancelled;  // empty: never cancelled
};

}  // namespace armature::server
