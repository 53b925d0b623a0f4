#include "armature/engine/kinematics/ik_two_bone.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "ik_internal.h"

namespace armature {
namespace {

using ik_internal::EffectorPoint;
using ik_internal::RotateJointInWorld;
using ik_internal::UpdateWorldOf;

// The component of `v` perpendicular to unit `axis`.
Eigen::Vector3d Perpendicular(const Eigen::Vector3d& v, const Eigen::Vector3d& axis) { return v - v.dot(axis) * axis; }

Eigen::Vector3d AnyPerpendicular(const Eigen::Vector3d& v) {
  const Eigen::Vector3d other =
      std::abs(v.normalized().x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return v.cross(other).normalized();
}

void SolveOne(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, const IkWorkspace::Effector& e,
              const IkEffector& in) {
  const int end = e.joint, mid = skeleton.parents[end], upper = skeleton.parents[mid];
  auto refresh_below = [&](int from) {
    if (from == upper) UpdateWorldOf(skeleton, ws, mid);
    UpdateWorldOf(skeleton, ws, end);
  };
  const Eigen::Vector3d a = ws.world_position[upper];
  // With a rotation target the end joint will turn; its effector point moves
  // with it, so the triangle is solved for the joint's origin instead.
  Eigen::Vector3d goal = e.target_position;
  Eigen::Vector3d end_point = EffectorPoint(ws, e);
  if (e.has_rotation) {
    const Eigen::Quaterniond turn = e.target_rotation * ws.world_rotation[end].conjugate();
    goal -= turn * (end_point - ws.world_position[end]);
    end_point = ws.world_position[end];
  }
  const double l1 = (ws.world_position[mid] - a).norm();
  const double l2 = (end_point - ws.world_position[mid]).norm();
  const Eigen::Vector3d to_goal = goal - a;
  const double distance = to_goal.norm();
  const double reach =
      std::clamp(SoftenedReach(distance, l1 + l2, request.options.softness), std::abs(l1 - l2), l1 + l2);

  const Eigen::Vector3d upper_bone = ws.world_position[mid] - a;
  const Eigen::Vector3d lower_bone = end_point - ws.world_position[mid];
  auto end_now = [&] { return e.has_rotation ? ws.world_position[end] : EffectorPoint(ws, e); };
  const Eigen::Vector3d line = distance > 1e-12 ? Eigen::Vector3d(to_goal / distance) : (end_point - a).normalized();
  if (upper_bone.cross(lower_bone).norm() < 1e-9 * l1 * l2) {
    // A straight limb has no bend plane of its own: build the triangle in the
    // plane of the goal line and the pole, and turn each bone onto its side.
    Eigen::Vector3d side = in.pole ? Perpendicular(*in.pole - a, line) : Eigen::Vector3d::Zero();
    side = side.norm() > 1e-12 ? Eigen::Vector3d(side.normalized()) : AnyPerpendicular(line);
    const double cos_upper =
        reach > 1e-12 ? std::clamp((l1 * l1 + reach * reach - l2 * l2) / (2 * l1 * reach), -1.0, 1.0) : 0.0;
    const Eigen::Vector3d knee = a + l1 * (cos_upper * line + std::sqrt(1 - cos_upper * cos_upper) * side);
    RotateJointInWorld(skeleton, request, ws, upper, Eigen::Quaterniond::FromTwoVectors(upper_bone, knee - a));
    refresh_below(upper);
    RotateJointInWorld(skeleton, request, ws, mid,
                       Eigen::Quaterniond::FromTwoVectors(end_now() - knee, a + reach * line - knee));
    refresh_below(mid);
  } else {
    // 1. Bend the middle joint about its current bend axis (a knee stays a
    //    hinge) to the exterior angle that spans `reach`.
    const Eigen::Vector3d axis = upper_bone.cross(lower_bone).normalized();
    const double current = std::atan2(upper_bone.cross(lower_bone).dot(axis), upper_bone.dot(lower_bone));
    const double cos_interior = std::clamp((l1 * l1 + l2 * l2 - reach * reach) / (2 * l1 * l2), -1.0, 1.0);
    const double wanted = std::numbers::pi - std::acos(cos_interior);
    RotateJointInWorld(skeleton, request, ws, mid, Eigen::Quaterniond(Eigen::AngleAxisd(wanted - current, axis)));
    refresh_below(mid);
    // 2. Turn the upper joint so the end points at the goal.
    if (distance > 1e-12) {
      RotateJointInWorld(skeleton, request, ws, upper, Eigen::Quaterniond::FromTwoVectors(end_now() - a, to_goal));
      refresh_below(upper);
    }
    // 3. Swing the limb about the goal line so the middle joint faces the pole.
    if (in.pole) {
      const Eigen::Vector3d knee = Perpendicular(ws.world_position[mid] - a, line);
      const Eigen::Vector3d pole = Perpendicular(*in.pole - a, line);
      if (knee.norm() > 1e-9 * l1 && pole.norm() > 1e-12) {
        const double angle = std::atan2(knee.cross(pole).dot(line), knee.dot(pole));
        RotateJointInWorld(skeleton, request, ws, upper, Eigen::Quaterniond(Eigen::AngleAxisd(angle, line)));
        refresh_below(upper);
      }
    }
  }
  if (e.has_rotation) ik_internal::SetWorldRotation(skeleton, request, ws, end, e.target_rotation);
}

}  // namespace

double SoftenedReach(double distance, double max_reach, double softness) {
  const double soft = softness * max_reach;
  const double start = max_reach - soft;
  if (soft <= 0 || distance <= start) return distance;
  return start + soft * (1.0 - std::exp(-(distance - start) / soft));
}

void SolveTwoBone(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, IkResult& result) {
  for (size_t i = 0; i < ws.effectors.size(); ++i) {
    // An earlier chain may have moved this one: bring its path up to date.
    for (int j : ws.update) ik_internal::UpdateWorldOf(skeleton, ws, j);
    SolveOne(skeleton, request, ws, ws.effectors[i], request.effectors[i]);
  }
  for (int j : ws.update) ik_internal::UpdateWorldOf(skeleton, ws, j);
  ik_internal::FinishResult(request, ws, 1, IkStop::kDone, result);
}

}  // namespace armature
