// Heavy unary calls (long evaluations) run here, not on gRPC's callback
// threads, which then stay free for cheap calls and the health service
// whatever heavy calls arrive (four 32-layer EvaluateMotion calls on the
// callback threads held Health/Check up for 17.8 s). A fixed number run at
// once and a bounded number wait; one more is refused at once with
// RESOURCE_EXHAUSTED naming the flags. A call whose deadline passed while it
// waited is answered without starting. Calls whose cost (work_budget.h) is
// at most kInlineWork run where they arrive (a thread hop would cost them
// more than they take), and so do those over the budget, refused at once.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include <grpcpp/grpcpp.h>

#include "armature/base/status.h"
#include "server/rpc/work/elastic_thread_pool.h"
#include "server/rpc/limits.h"

namespace armature::server {

class HeavyCallPool {
 public:
  static constexpr int64_t kInlineWork = 250000;  // joint samples: about 17 ms at 70 ns each

  // --heavy-threads and --heavy-queue (0: their defaults).
  explicit HeavyCallPool(const Limits& limits);

  // Runs `work` (it fills the response and returns the status) and finishes
  // the call with its status; `where` names the call in errors and logs.
  grpc::ServerUnaryReactor* Run(grpc::CallbackServerContext* context, const std::string& where, int64_t cost,
                                std::function<Status()> work);

 private:
  const int64_t max_request_work_;
  const size_t threads_;
  const size_t queue_;
  std::atomic<size_t> admitted_{0};  // running or waiting
  ElasticThreadPool pool_;           // last: destroyed first, running what is queued
};

}  // namespace armature::server
