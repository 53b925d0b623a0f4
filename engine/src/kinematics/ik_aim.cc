#include "armature/engine/kinematics/ik_aim.h"

#include <algorithm>
#include <cmath>

#include "ik_internal.h"

namespace armature {
namespace {

// The world rotation taking the joint-local frame (aim, up) onto the world
// frame (forward, up hint), the up directions made perpendicular first; or
// nothing when the hint is parallel to `forward`.
std::optional<Eigen::Quaterniond> FrameRotation(const Eigen::Vector3d& aim, const Eigen::Vector3d& up,
                                                const Eigen::Vector3d& forward, const Eigen::Vector3d& up_hint) {
  const Eigen::Vector3d world_up = up_hint - up_hint.dot(forward) * forward;
  if (world_up.norm() < 1e-9 * up_hint.norm()) return std::nullopt;
  const Eigen::Vector3d local_up = (up - up.dot(aim) * aim).normalized();
  Eigen::Matrix3d local, world;
  local << aim, local_up, aim.cross(local_up);
  const Eigen::Vector3d w_up = world_up.normalized();
  world << forward, w_up, forward.cross(w_up);
  return Eigen::Quaterniond(world * local.transpose());
}

}  // namespace

void SolveAim(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, IkResult& result) {
  for (size_t i = 0; i < ws.effectors.size(); ++i) {
    const IkWorkspace::Effector& e = ws.effectors[i];
    const IkEffector& in = request.effectors[i];
    ik_internal::UpdateWorld(skeleton, ws, ws.update);  // an earlier aim may have moved this joint
    const Eigen::Vector3d to_target = e.target_position - ws.world_position[e.joint];
    if (to_target.norm() < 1e-12) continue;
    const Eigen::Vector3d forward = to_target.normalized();
    const Eigen::Vector3d aim = in.aim_axis.normalized();
    std::optional<Eigen::Quaterniond> frame;
    if (in.up_hint) frame = FrameRotation(aim, in.up_axis.normalized(), forward, *in.up_hint);
    if (frame) {
      ik_internal::SetWorldRotation(skeleton, request, ws, e.joint, *frame);
    } else {
      ik_internal::RotateJointInWorld(skeleton, request, ws, e.joint,
                                      Eigen::Quaterniond::FromTwoVectors(ws.world_rotation[e.joint] * aim, forward));
    }
  }
  ik_internal::UpdateWorld(skeleton, ws, ws.update);
  ik_internal::FinishResult(request, ws, 1, IkStop::kDone, result);
  // Aim residuals: how far the aim ray misses each target.
  result.converged = true;
  for (size_t i = 0; i < ws.effectors.size(); ++i) {
    const IkWorkspace::Effector& e = ws.effectors[i];
    const Eigen::Vector3d axis = ws.world_rotation[e.joint] * request.effectors[i].aim_axis.normalized();
    const Eigen::Vector3d to_target = e.target_position - ws.world_position[e.joint];
    const double along = to_target.dot(axis);
    IkEffectorResidual& r = result.residuals[i];
    r.rotation_error = std::atan2(axis.cross(to_target).norm(), along);
    r.position_error = along > 0 ? (to_target - along * axis).norm() : to_target.norm();
    r.reached = r.rotation_error <= request.options.rotation_tolerance;
    result.converged = result.converged && r.reached;
  }
  result.stop = result.converged ? IkStop::kConverged : IkStop::kDone;
}

}  // namespace armature
