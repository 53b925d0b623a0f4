// Aim / look-at: turn a joint (a head, a camera) so a joint-local axis points
// at a target, with an optional up hint fixing the roll; within its limit.
#pragma once

#include "armature/engine/kinematics/ik_types.h"
#include "armature/engine/kinematics/ik_workspace.h"
#include "armature/engine/anim/skeleton.h"

namespace armature {

// Effectors in order (a neck, then the head). Residuals: rotation_error is the
// angle between the aim axis and the target direction, position_error the
// target's distance from the aim ray. Precondition: PrepareIkWorkspace succeeded.
void SolveAim(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, IkResult& result);

}  // namespace armature
