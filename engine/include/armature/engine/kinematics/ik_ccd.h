// Cyclic coordinate descent: sweeping from the effector up the chain, each
// free joint turns so the effector point lines up with the target (hinges
// about their axis), within its limit.
#pragma once

#include "armature/engine/kinematics/ik_types.h"
#include "armature/engine/kinematics/ik_workspace.h"
#include "armature/engine/anim/skeleton.h"

namespace armature {

// One effector with a target position; a rotation target is applied to the
// effector joint after each sweep. Precondition: PrepareIkWorkspace succeeded.
void SolveCcd(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, IkResult& result);

}  // namespace armature
