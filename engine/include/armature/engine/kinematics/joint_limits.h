// Joint limits: checking a limit, projecting a rotation onto it and sampling
// inside it. Rotations here are Δ = rest.rotation⁻¹ · local.rotation.
#pragma once

#include <string_view>

#include <Eigen/Geometry>

#include "armature/engine/kinematics/ik_types.h"
#include "armature/base/status.h"

namespace armature {

// INVALID_ARGUMENT naming the field under `field` (e.g. "limits[2]"):
// min_deg > max_deg, a negative or > 180 cone, twist_min > twist_max, a zero
// axis, equal neighbouring Euler axes, ranges wider than 360° or not finite.
Status ValidateJointLimit(const JointLimit& limit, std::string_view field);

// The 2π turn of `angle` nearest [lo, hi] (radians), clamped into it.
double ClampAngle(double angle, double lo, double hi);

// Δ = swing · twist with twist about `unit_axis`; angles in radians, twist
// in (−π, π], swing in [0, π].
struct SwingTwist {
  Eigen::Quaterniond swing;
  Eigen::Quaterniond twist;
  double swing_angle = 0;
  double twist_angle = 0;
};
SwingTwist DecomposeSwingTwist(const Eigen::Quaterniond& delta, const Eigen::Vector3d& unit_axis);

// Euler angles (radians, in the limit's order) of Δ clamped to the limit's
// box, taking of the two Euler solutions (and their 2π turns) the one whose
// clamped rotation is nearest Δ. A Δ inside the limit round-trips exactly.
Eigen::Vector3d ClampedEulerAngles(const JointLimit& limit, const Eigen::Quaterniond& delta);

// The allowed rotation nearest Δ (Euler: the clamped angles; swing-twist:
// swing and twist clamped separately). Δ inside the limit is returned as is.
Eigen::Quaterniond ProjectToLimit(const JointLimit& limit, const Eigen::Quaterniond& delta);

// Whether Δ satisfies the limit, with `slack_rad` of tolerance.
bool WithinLimit(const JointLimit& limit, const Eigen::Quaterniond& delta, double slack_rad = 1e-9);

// A rotation inside the limit from three uniform numbers in [0, 1): Euler
// angles uniform in their ranges; swing-twist with the swing direction
// uniform and its angle spread over the cone's area, the twist uniform.
Eigen::Quaterniond SampleWithinLimit(const JointLimit& limit, const Eigen::Vector3d& uniform01);

}  // namespace armature
