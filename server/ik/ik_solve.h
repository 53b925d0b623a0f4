// One IK solve from a converted call to its answer, shared by the unary
// SolveIk handler and the IkSession reactor.
#pragma once

#include "armature/base/status.h"
#include "armature/engine/kinematics/ik_workspace.h"
#include "armature/v1/ik.pb.h"
#include "server/ik/ik_convert.h"
#include "server/rpc/pose_convert.h"

namespace armature::server {

// Solves `call` (its request carrying any deadline and cancel check) and
// writes the answer. INVALID_ARGUMENT naming the API field for bad input;
// DEADLINE_EXCEEDED or CANCELLED when interrupted; an unreachable target is OK.
Status RunIk(const IkCall& call, IkWorkspace& workspace, IkResult& result, PoseWorkspace& pose,
             v1::SolveIkResponse* response);

}  // namespace armature::server
