// Long work's look at its call as it goes: the one deadline and
// cancellation check every heavy loop uses, so no CPU is spent on an answer
// nobody waits for. The clock is read once per kCheckWork units of work,
// not per step, so the check costs nothing next to the work.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include <grpcpp/grpcpp.h>

#include "armature/base/status.h"

namespace armature::server {

class CallProgress {
 public:
  static constexpr int64_t kCheckWork = 1 << 16;  // joint samples between looks (well under a millisecond)

  // No call behind the work (tests, benchmarks): it never stops.
  CallProgress() = default;
  // `where` names the call in errors ("EvaluateMotion"), `steps` what one step is ("times").
  CallProgress(const grpc::ServerContextBase& context, std::string where, std::string steps);

  // One more step of `work` units done: OK, or, past the deadline or after
  // the client cancelled, DEADLINE_EXCEEDED / CANCELLED saying after how many steps.
  Status Step(int64_t work) {
    ++steps_done_;
    unchecked_ += work;
    if (unchecked_ < kCheckWork) return Status::Ok();
    unchecked_ = 0;
    return Check();
  }
  // Looks now (also before any work: a call that waited past its deadline).
  Status Check() const;

 private:
  const grpc::ServerContextBase* context_ = nullptr;
  std::optional<std::chrono::steady_clock::time_point> deadline_;
  std::string where_, steps_;
  int64_t steps_done_ = 0;
  int64_t unchecked_ = 0;
};

}  // namespace armature::server
