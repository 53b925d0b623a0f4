#include "armature/engine/kinematics/ik.h"

#include "armature/engine/kinematics/ik_aim.h"
#include "armature/engine/kinematics/ik_ccd.h"
#include "armature/engine/kinematics/ik_dls.h"
#include "armature/engine/kinematics/ik_fabrik.h"
#include "armature/engine/kinematics/ik_two_bone.h"

namespace armature {

Status SolveIk(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& workspace, IkResult& result) {
  ARMATURE_RETURN_IF_ERROR(PrepareIkWorkspace(skeleton, request, workspace));
  result.restarts = 0;
  switch (request.solver) {
    case IkSolver::kDls: SolveDls(skeleton, request, workspace, result); break;
    case IkSolver::kTwoBone: SolveTwoBone(skeleton, request, workspace, result); break;
    case IkSolver::kCcd: SolveCcd(skeleton, request, workspace, result); break;
    case IkSolver::kFabrik: SolveFabrik(skeleton, request, workspace, result); break;
    case IkSolver::kAim: SolveAim(skeleton, request, workspace, result); break;
    default:
      return Status::InvalidArgument("solver: unknown value " + std::to_string(static_cast<int>(request.solver)));
  }
  return Status::Ok();
}

Status IkStopStatus(const IkResult& result) {
  switch (result.stop) {
    case IkStop::kDeadline: return Status::DeadlineExceeded("inverse kinematics: deadline reached before convergence");
    case IkStop::kCancelled: return Status::Cancelled("inverse kinematics: cancelled");
    default: return Status::Ok();
  }
}

}  // namespace armature
