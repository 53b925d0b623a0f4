#include "server/ik/ik_solve.h"

#include "armature/engine/kinematics/ik.h"
#include "server/rpc/grpc_status.h"

namespace armature::server {

Status RunIk(const IkCall& call, IkWorkspace& workspace, IkResult& result, PoseWorkspace& pose,
             v1::SolveIkResponse* response) {
  ARMATURE_RETURN_IF_ERROR(
      ApiFieldNames(armature::SolveIk(*call.skeleton.part->skeleton, call.request, workspace, result)));
  ARMATURE_RETURN_IF_ERROR(IkStopStatus(result));
  IkResponseToProto(call, result, pose, response);
  return Status::Ok();
}

}  // namespace armature::server
