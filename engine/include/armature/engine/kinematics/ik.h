// Inverse kinematics entry point: one request in, one result out.
#pragma once

#include "armature/engine/kinematics/ik_types.h"
#include "armature/engine/kinematics/ik_workspace.h"
#include "armature/engine/anim/skeleton.h"
#include "armature/base/status.h"

namespace armature {

// Validates `request` against `skeleton` (bad input: INVALID_ARGUMENT naming
// the field) and solves it with request.solver into `result`. A deadline or
// a cancel is not an error here: the result holds the best pose so far with
// stop = kDeadline or kCancelled (see IkStopStatus). `workspace` may be
// reused across requests.
Status SolveIk(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& workspace, IkResult& result);

// DEADLINE_EXCEEDED or CANCELLED for a result stopped that way, else OK:
// what an RPC handler returns.
Status IkStopStatus(const IkResult& result);

}  // namespace armature
