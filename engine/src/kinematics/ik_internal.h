// Pieces the IK solvers share: partial forward kinematics on the workspace,
// effector residuals, joint rotation under limits, deadline checks.
// Private to the engine.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <span>

#include <Eigen/Geometry>

#include "armature/engine/kinematics/ik_types.h"
#include "armature/engine/kinematics/ik_workspace.h"
#include "armature/engine/anim/skeleton.h"

namespace armature::ik_internal {

// World transform of `joint` from its parent's (already current).
inline void UpdateWorldOf(const Skeleton& skeleton, IkWorkspace& ws, int joint) {
  const Trs& l = ws.local[joint];
  const int p = skeleton.parents[joint];
  Eigen::Matrix3d r = l.rotation.toRotationMatrix();
  if ((l.scale.array() != 1.0).any()) r = r * l.scale.asDiagonal();
  if (p < 0) {
    ws.world_rotation[joint] = l.rotation;
    ws.world_linear[joint] = r;
    ws.world_position[joint] = l.translation;
  } else {
    ws.world_rotation[joint] = ws.world_rotation[p] * l.rotation;
    ws.world_linear[joint].noalias() = ws.world_linear[p] * r;
    ws.world_position[joint].noalias() = ws.world_position[p] + ws.world_linear[p] * l.translation;
  }
}

// Joints in ascending order, so parents come first.
inline void UpdateWorld(const Skeleton& skeleton, IkWorkspace& ws, std::span<const int> joints) {
  for (int j : joints) UpdateWorldOf(skeleton, ws, j);
}

inline Eigen::Vector3d EffectorPoint(const IkWorkspace& ws, const IkWorkspace::Effector& e) {
  return ws.world_position[e.joint] + ws.world_linear[e.joint] * e.offset;
}

// A world-space move of `joint`'s origin as a change of its local translation
// (the parent's rotation and scale taken out: a body root may hang below a
// scaled, turned node).
inline Eigen::Vector3d WorldMoveToLocal(const Skeleton& skeleton, const IkWorkspace& ws, int joint,
                                        const Eigen::Vector3d& move) {
  const int parent = skeleton.parents[joint];
  return parent < 0 ? move : Eigen::Vector3d(ws.world_linear[parent].inverse() * move);
}

inline Eigen::Quaterniond ParentWorldRotation(const Skeleton& skeleton, const IkWorkspace& ws, int joint) {
  const int p = skeleton.parents[joint];
  return p < 0 ? Eigen::Quaterniond::Identity() : ws.world_rotation[p];
}

// World-space rotation error (rotation vector taking the current rotation to
// the target) of an effector with a rotation target.
Eigen::Vector3d RotationResidual(const IkWorkspace& ws, const IkWorkspace::Effector& e);

// Fills one residual per effector; true when every effector is reached.
bool MeasureResiduals(const IkWorkspace& ws, double rotation_tolerance, std::span<IkEffectorResidual> out);

// kDeadline or kCancelled when the request says to stop now.
std::optional<IkStop> CheckInterrupt(const IkRequest& request);

// Local rotation projected onto the joint's limit, if it has one.
Eigen::Quaterniond Limited(const Skeleton& skeleton, const IkRequest& request, const IkWorkspace& ws, int joint,
                           const Eigen::Quaterniond& local_rotation);

// Pre-multiplies the joint's world rotation by `world_delta` (about the
// joint's origin), within its limit. Only the joint's own world transform
// is updated; descendants are the caller's business.
void RotateJointInWorld(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, int joint,
                        const Eigen::Quaterniond& world_delta);

// The world axis of a hinge (a swing-twist limit with a zero cone), if
// `joint` is one.
std::optional<Eigen::Vector3d> HingeAxis(const Skeleton& skeleton, const IkRequest& request, const IkWorkspace& ws,
                                         int joint);

// Turns `joint` about the world `axis` through its origin, within its
// limit, so that the world point `from` moves towards `to` (seen along the
// axis). Returns the world rotation actually applied.
Eigen::Quaterniond TurnJointAbout(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, int joint,
                                  const Eigen::Vector3d& axis, const Eigen::Vector3d& from, const Eigen::Vector3d& to);

// Turns `joint` about its origin, within its limit, so that the world point
// `from` moves towards `to` (a hinge turns about its axis only). Returns the
// world rotation actually applied.
Eigen::Quaterniond TurnJointTowards(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, int joint,
                                    const Eigen::Vector3d& from, const Eigen::Vector3d& to);

// Gives `joint` the world rotation `target` as nearly as its limit allows.
void SetWorldRotation(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, int joint,
                      const Eigen::Quaterniond& target);

// Fills result.pose and residuals from the workspace and sets converged and
// stop (`stop` unless every effector is reached).
void FinishResult(const IkRequest& request, const IkWorkspace& ws, int iterations, IkStop stop, IkResult& result);

// CheckInterrupt every `every` calls: a sweep over a long chain looks at
// the clock and the cancel flag often enough without paying for it per joint.
class InterruptPoll {
 public:
  InterruptPoll(const IkRequest& request, int every) : request_(request), every_(every) {}
  std::optional<IkStop> operator()() {
    if (++calls_ < every_) return std::nullopt;
    calls_ = 0;
    return CheckInterrupt(request_);
  }

 private:
  const IkRequest& request_;
  int every_;
  int calls_ = 0;
};

// Drives a single-chain solver (CCD, FABRIK): `sweep()` moves the chain
// once and returns the interrupt that cut it short, if any (one sweep over
// a long chain can outlast the deadline); between sweeps the pose is
// re-read, the effector joint is turned to its rotation target, and the loop
// ends when the effector is reached, the sweeps stop improving, the
// iteration cap or the deadline.
template <class Sweep>
void SweepUntilReached(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, IkResult& result,
                       Sweep&& sweep) {
  const IkWorkspace::Effector& e = ws.effectors[0];
  result.residuals.resize(1);
  double best = INFINITY;
  int idle = 0, iterations = 0;
  IkStop stop = IkStop::kIterationCap;
  while (true) {
    if (MeasureResiduals(ws, request.options.rotation_tolerance, result.residuals)) break;
    const double error = result.residuals[0].position_error + result.residuals[0].rotation_error * ws.chain_length;
    if (error < best * (1 - 1e-9)) {
      best = error, idle = 0;
    } else if (++idle >= 4) {
      stop = IkStop::kStalled;
      break;
    }
    if (iterations >= request.options.max_iterations) break;
    if (const std::optional<IkStop> interrupt = CheckInterrupt(request)) {
      stop = *interrupt;
      break;
    }
    const std::optional<IkStop> interrupted = sweep();
    UpdateWorld(skeleton, ws, ws.update);
    if (interrupted) {
      stop = *interrupted;
      ++iterations;
      break;
    }
    if (e.has_rotation) {
      SetWorldRotation(skeleton, request, ws, e.joint, e.target_rotation);
      UpdateWorld(skeleton, ws, ws.update);
    }
    ++iterations;
  }
  FinishResult(request, ws, iterations, stop, result);
}

// Uniform in [0, 1) from a splitmix64 stream: cheap to seed per request.
double NextUniform(uint64_t& state);

}  // namespace armature::ik_internal
