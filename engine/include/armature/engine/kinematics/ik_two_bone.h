// Analytic two-bone IK (hip-knee-ankle, shoulder-elbow-wrist): the middle
// joint bends about its current bend axis to the law-of-cosines angle, the
// upper joint turns the end onto the target, then the limb turns about the
// upper→target line so the middle joint lies towards the pole.
#pragma once

#include "armature/engine/kinematics/ik_types.h"
#include "armature/engine/kinematics/ik_workspace.h"
#include "armature/engine/anim/skeleton.h"

namespace armature {

// The distance the limb actually reaches for a target `distance` away when
// fully extended it spans `max_reach`: unchanged up to (1 − softness) ×
// max_reach, then easing exponentially towards max_reach without getting
// there, with a continuous slope, so the limb never snaps straight.
double SoftenedReach(double distance, double max_reach, double softness);

// Solves each effector's chain (effector joint, parent, grandparent) in turn.
// Precondition: PrepareIkWorkspace(skeleton, request, ws) succeeded.
void SolveTwoBone(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, IkResult& result);

}  // namespace armature
