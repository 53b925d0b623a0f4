#include "server/rpc/work/call_progress.h"

#include "server/rpc/grpc_status.h"

namespace armature::server {

CallProgress::CallProgress(const grpc::ServerContextBase& context, std::string where, std::string steps)
    : context_(&context), deadline_(SteadyDeadline(context)), where_(std::move(where)), steps_(std::move(steps)) {}

Status CallProgress::Check() const {
  if (context_ == nullptr) return Status::Ok();
  const std::string after =
      steps_done_ == 0 ? " before any work began"
                       : " after " + std::to_string(steps_done_) + " " + steps_ + "; the rest was not computed";
  if (deadline_ && std::chrono::steady_clock::now() >= *deadline_)
    return Status::DeadlineExceeded(where_ + ": the call's deadline passed" + after);
  if (context_->IsCancelled()) return Status::Cancelled(where_ + ": the client cancelled the call" + after);
  return Status::Ok();
}

}  // namespace armature::server
