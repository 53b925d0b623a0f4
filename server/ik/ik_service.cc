#include "server/ik/ik_service.h"

#include "armature/engine/kinematics/ik.h"
#include "server/rpc/call_guard.h"
#include "server/rpc/grpc_status.h"
#include "server/ik/ik_session_reactor.h"
#include "server/ik/ik_solve.h"

namespace armature::server {

// The per-thread workspace keeps its buffers' capacity between calls; one
// large request must not pin them (3,000 effectors left 1.3 GB per thread).
static void ReleaseIfLarge(IkWorkspace& ws) {
  constexpr Eigen::Index kKeptElements = 1 << 20;  // 8 MiB of doubles
  // Swapped with a fresh one rather than move-assigned: GCC 12 warns (-Wmaybe-uninitialized, a
  // false positive) on Eigen::LLT's move assignment of a default-constructed LLT.
  if (ws.jacobian.size() + ws.hessian.size() + ws.damped.size() + ws.gram.size() > kKeptElements) {
    IkWorkspace fresh;
    std::swap(ws, fresh);
  }
}

grpc::ServerUnaryReactor* IkServiceImpl::SolveIk(grpc::CallbackServerContext* context,
                                                 const v1::SolveIkRequest* request,
                                                 v1::SolveIkResponse* response) {
  return RunUnary(context, "SolveIk", [&]() -> Status {
    IkCall call;
    Status status = IkCallFromProto(*store_.Snapshot(), limits_, *request, call);
    if (status.ok()) {
      // The solver stops at the call's deadline or when the client cancels,
      // so no CPU is spent on an answer nobody waits for.
      call.request.deadline = SteadyDeadline(*context);
      call.request.should_stop = [context] { return context->IsCancelled(); };
      thread_local IkWorkspace workspace;  // reused across calls on this thread
      thread_local IkResult result;
      thread_local PoseWorkspace pose;
      status = RunIk(call, workspace, result, pose, response);
      ReleaseIfLarge(workspace);
    }
    return status;
  });
}

grpc::ServerBidiReactor<v1::IkSessionRequest, v1::SolveIkResponse>* IkServiceImpl::IkSession(
    grpc::CallbackServerContext* context) {
  return MakeReactor<grpc::ServerBidiReactor<v1::IkSessionRequest, v1::SolveIkResponse>>(context, "IkSession", [&]() -> grpc::ServerBidiReactor<v1::IkSessionRequest, v1::SolveIkResponse>* {
    using Base = grpc::ServerBidiReactor<v1::IkSessionRequest, v1::SolveIkResponse>;
    auto stream = streams_->Admit(*context, "IkSession");
    if (!stream.ok()) return new FinishedReactor<Base>(stream.status());
    return new IkSessionReactor(context, store_, limits_, *sessions_, std::move(*stream));
  });
}

}  // namespace armature::server
