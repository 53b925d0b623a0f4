// FABRIK (Aristidou & Lasenby): joint positions are moved backward from the
// target and forward from the fixed base keeping bone lengths, then turned
// back into joint rotations top-down (hinges about their axis, within
// limits) and re-read from forward kinematics, so limits shape the next pass.
#pragma once

#include "armature/engine/kinematics/ik_types.h"
#include "armature/engine/kinematics/ik_workspace.h"
#include "armature/engine/anim/skeleton.h"

namespace armature {

// One effector with a target position; a rotation target is applied to the
// effector joint after each pass. Precondition: PrepareIkWorkspace succeeded.
void SolveFabrik(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, IkResult& result);

}  // namespace armature
