// Damped least squares (Levenberg–Marquardt) over every free joint, for
// several effectors with position and/or rotation targets at once.
//
// Unknowns: per free joint an increment on top of its current rotation —
// a world rotation vector (unlimited and swing-twist joints), the Euler
// angles of an Euler-limited joint, the angle of a hinge — and optionally the
// root translation. Jacobian columns are analytic: ω × (p_e − p_j) for
// positions (normalized by the chain length), ω for rotations. Each step
// solves (JᵀWJ + μI) δ = JᵀWr by Cholesky, with Nielsen's adaptive μ.
// Bounds: Euler and hinge angles are clamped, and coordinates held at a
// bound that the gradient pushes against are frozen for the step (an active
// set), as are the swing/twist directions of a cone at its edge; cone joints
// are projected onto their limit. A coordinate starting on a bound (a
// straight knee at 0°) starts a fifth of its range inside: there the reach
// problem has a saddle whose gradient points out of range. When progress
// stalls short of the target the best pose is perturbed (bound coordinates
// to mid-range, then near, then anywhere within the limits) and solving
// resumes, a bounded number of times. Once reached,
// options.regularization > 0 slides the pose along the solutions towards the
// start pose (null-space steps).
#pragma once

#include "armature/engine/kinematics/ik_types.h"
#include "armature/engine/kinematics/ik_workspace.h"
#include "armature/engine/anim/skeleton.h"

namespace armature {

// Precondition: PrepareIkWorkspace(skeleton, request, ws) succeeded.
void SolveDls(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, IkResult& result);

}  // namespace armature
