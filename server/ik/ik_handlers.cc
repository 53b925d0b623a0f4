#include "server/ik/ik_handlers.h"

#include <utility>

#include "armature/engine/kinematics/ik.h"
#include "server/rpc/grpc_status.h"

namespace armature::server {
namespace {
// The per-thread workspace keeps its buffers' capacity between calls; one
// large request must not pin them (3,000 effectors left 1.3 GB per thread).
void ReleaseIfLarge(IkWorkspace& ws) {
  constexpr Eigen::Index kKeptElements = 1 << 20;  // 8 MiB of doubles
  // Swapped with a fresh one rather than move-assigned: GCC 12 warns (-Wmaybe-uninitialized, a
  // false positive) on Eigen::LLT's move assignment of a default-constructed LLT.
  if (ws.jacobian.size() + ws.hessian.size() + ws.damped.size() + ws.gram.size() > kKeptElements) {
    IkWorkspace fresh;
    std::swap(ws, fresh);
  }
}
}  // namespace

Status RunIk(const IkCall& call, IkWorkspace& workspace, IkResult& result, PoseWorkspace& pose,
             v1::SolveIkResponse* response) {
  ARMATURE_RETURN_IF_ERROR(
      ApiFieldNames(armature::SolveIk(*call.skeleton.part->skeleton, call.request, workspace, result)));
  ARMATURE_RETURN_IF_ERROR(IkStopStatus(result));
  IkResponseToProto(call, result, pose, response);
  return Status::Ok();
}

Status SolveIk(const Catalog& catalog, const Limits& limits, const v1::SolveIkRequest& request,
               v1::SolveIkResponse* response, const CallStop& stop) {
  IkCall call;
  ARMATURE_RETURN_IF_ERROR(IkCallFromProto(catalog, limits, request, call));
  call.request.deadline = stop.deadline;
  call.request.should_stop = stop.cancelled;
  thread_local IkWorkspace workspace;  // reused across calls on this thread
  thread_local IkResult result;
  thread_local PoseWorkspace pose;
  const Status status = RunIk(call, workspace, result, pose, response);
  ReleaseIfLarge(workspace);
  return status;
}

}  // namespace armature::server
