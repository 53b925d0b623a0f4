#include <chrono>
#include <cmath>

#include "armature/engine/kinematics/joint_limits.h"
#include "armature/engine/math/rotation.h"
#include "ik_internal.h"

namespace armature::ik_internal {

Eigen::Vector3d RotationResidual(const IkWorkspace& ws, const IkWorkspace::Effector& e) {
  return LogQuaternion(e.target_rotation * ws.world_rotation[e.joint].conjugate());
}

bool MeasureResiduals(const IkWorkspace& ws, double rotation_tolerance, std::span<IkEffectorResidual> out) {
  bool all = true;
  for (size_t i = 0; i < ws.effectors.size(); ++i) {
    const IkWorkspace::Effector& e = ws.effectors[i];
    IkEffectorResidual& r = out[i];
    r.position_error = e.has_position ? (e.target_position - EffectorPoint(ws, e)).norm() : 0.0;
    r.rotation_error = e.has_rotation ? RotationResidual(ws, e).norm() : 0.0;
    r.reached = r.position_error <= ws.position_tolerance && r.rotation_error <= rotation_tolerance;
    r.body_root = e.body_root;
    all = all && r.reached;
  }
  return all;
}

std::optional<IkStop> CheckInterrupt(const IkRequest& request) {
  if (request.should_stop && request.should_stop()) return IkStop::kCancelled;
  if (request.deadline && std::chrono::steady_clock::now() >= *request.deadline) return IkStop::kDeadline;
  return std::nullopt;
}

Eigen::Quaterniond Limited(const Skeleton& skeleton, const IkRequest& request, const IkWorkspace& ws, int joint,
                           const Eigen::Quaterniond& local_rotation) {
  const int l = ws.limit_of[joint];
  if (l < 0) return local_rotation.normalized();
  const Eigen::Quaterniond& rest = skeleton.rest[joint].rotation;
  return (rest * ProjectToLimit(request.limits[l], rest.conjugate() * local_rotation)).normalized();
}

void RotateJointInWorld(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, int joint,
                        const Eigen::Quaterniond& world_delta) {
  SetWorldRotation(skeleton, request, ws, joint, world_delta * ws.world_rotation[joint]);
}

std::optional<Eigen::Vector3d> HingeAxis(const Skeleton& skeleton, const IkRequest& request, const IkWorkspace& ws,
                                         int joint) {
  const int l = ws.limit_of[joint];
  if (l < 0 || request.limits[l].kind != JointLimit::Kind::kSwingTwist || request.limits[l].cone_deg != 0)
    return std::nullopt;
  return ParentWorldRotation(skeleton, ws, joint) *
         (skeleton.rest[joint].rotation * request.limits[l].axis.normalized());
}

Eigen::Quaterniond TurnJointAbout(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, int joint,
                                  const Eigen::Vector3d& axis, const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  const Eigen::Vector3d origin = ws.world_position[joint];
  Eigen::Vector3d v1 = from - origin, v2 = to - origin;
  v1 -= v1.dot(axis) * axis;
  v2 -= v2.dot(axis) * axis;
  if (v1.norm() < 1e-12 || v2.norm() < 1e-12) return Eigen::Quaterniond::Identity();
  const Eigen::Quaterniond before = ws.world_rotation[joint];
  RotateJointInWorld(skeleton, request, ws, joint,
                     Eigen::Quaterniond(Eigen::AngleAxisd(std::atan2(v1.cross(v2).dot(axis), v1.dot(v2)), axis)));
  return ws.world_rotation[joint] * before.conjugate();
}

Eigen::Quaterniond TurnJointTowards(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, int joint,
                                    const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  if (const std::optional<Eigen::Vector3d> axis = HingeAxis(skeleton, request, ws, joint))
    return TurnJointAbout(skeleton, request, ws, joint, *axis, from, to);
  const Eigen::Vector3d origin = ws.world_position[joint];
  const Eigen::Vector3d v1 = from - origin, v2 = to - origin;
  if (v1.norm() < 1e-12 || v2.norm() < 1e-12) return Eigen::Quaterniond::Identity();
  const Eigen::Quaterniond before = ws.world_rotation[joint];
  RotateJointInWorld(skeleton, request, ws, joint, Eigen::Quaterniond::FromTwoVectors(v1, v2));
  return ws.world_rotation[joint] * before.conjugate();
}

void SetWorldRotation(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, int joint,
                      const Eigen::Quaterniond& target) {
  const Eigen::Quaterniond local = ParentWorldRotation(skeleton, ws, joint).conjugate() * target;
  ws.local[joint].rotation = Limited(skeleton, request, ws, joint, local);
  UpdateWorldOf(skeleton, ws, joint);
}

void FinishResult(const IkRequest& request, const IkWorkspace& ws, int iterations, IkStop stop, IkResult& result) {
  result.pose.assign(ws.local.begin(), ws.local.end());
  result.residuals.resize(ws.effectors.size());
  result.converged = MeasureResiduals(ws, request.options.rotation_tolerance, result.residuals);
  result.iterations = iterations;
  result.stop = result.converged ? IkStop::kConverged : stop;
}

double NextUniform(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

}  // namespace armature::ik_internal
