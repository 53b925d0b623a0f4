#include "server/rpc/work/heavy_call_pool.h"

#include <algorithm>
#include <thread>

#include "server/rpc/call_guard.h"
#include "server/rpc/work/call_progress.h"
#include "server/rpc/grpc_status.h"

namespace armature::server {
namespace {

size_t ThreadsOf(const Limits& limits) {
  if (limits.heavy_threads > 0) return static_cast<size_t>(limits.heavy_threads);
  return std::max<size_t>(2, std::thread::hardware_concurrency());
}

}  // namespace

HeavyCallPool::HeavyCallPool(const Limits& limits)
    : max_request_work_(limits.max_request_work),
      threads_(ThreadsOf(limits)),
      queue_(limits.heavy_queue > 0 ? static_cast<size_t>(limits.heavy_queue) : 4 * threads_),
      pool_(threads_) {}

grpc::ServerUnaryReactor* HeavyCallPool::Run(grpc::CallbackServerContext* context, const std::string& where,
                                             int64_t cost, std::function<Status()> work) {
  // Cheap calls, and calls over --max-request-work (the handler refuses them at once), run here.
  if (cost <= kInlineWork || cost > max_request_work_) return RunUnary(context, where, work);
  grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
  if (admitted_.fetch_add(1) >= threads_ + queue_) {
    admitted_.fetch_sub(1);
    reactor->Finish(ToGrpcStatus(Status::ResourceExhausted(
        where + ": the server is busy: " + std::to_string(threads_ + queue_) +
        " heavy calls are running or waiting, the most it takes (--heavy-threads " + std::to_string(threads_) +
        " running, --heavy-queue " + std::to_string(queue_) + " waiting); try again later")));
    return reactor;
  }
  try {
    pool_.Enqueue([this, context, reactor, where, work = std::move(work)] {
      Status status = CallProgress(*context, where, "steps").Check();
      if (status.ok()) status = Guarded(context, where, work);
      admitted_.fetch_sub(1);  // before the answer: the caller may send the next at once
      reactor->Finish(ToGrpcStatus(status));
    });
  } catch (...) {  // could not even queue it
    admitted_.fetch_sub(1);
    reactor->Finish(ToGrpcStatus(StatusOfCurrentException(context, where)));
  }
  return reactor;
}

}  // namespace armature::server
