// Inverse kinematics vocabulary: what a caller asks for (IkRequest) and what
// it gets back (IkResult). Joints are named, so a request maps 1:1 onto an
// RPC message; SolveIk (ik.h) resolves the names and reports bad input as
// INVALID_ARGUMENT naming the field, e.g. "effectors[1].joint: unknown joint
// 'LeftHandd'".
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "armature/engine/math/rotation.h"
#include "armature/engine/math/transform.h"

namespace armature {

enum class IkSolver : unsigned char {
  kDls,      // damped least squares (Levenberg–Marquardt) over every free joint; all effectors at once
  kTwoBone,  // analytic: effector joint, its parent and grandparent (hip-knee-ankle); one chain per effector
  kCcd,      // cyclic coordinate descent along one effector's chain
  kFabrik,   // forward-and-backward reaching along one effector's chain
  kAim,      // rotate each effector joint so a local axis points at its target
};

// A goal for one joint. Targets are in world space (the frame of the pose's
// root transforms).
struct IkEffector {
  std::string joint;
  // The point that must reach target_position, in the joint's frame (e.g. its
  // end site); zero = the joint's origin.
  Eigen::Vector3d local_offset = Eigen::Vector3d::Zero();
  std::optional<Eigen::Vector3d> target_position;
  // The joint's world rotation (the product of local rotations).
  std::optional<Eigen::Quaterniond> target_rotation;
  // Relative importance in DLS. A position error of one chain length weighs
  // as much as a rotation error of one radian at equal weights.
  double position_weight = 1.0;
  double rotation_weight = 1.0;
  // Two-bone: a world point the middle joint bends towards (a knee or elbow
  // target). Without it the current bend plane is kept.
  std::optional<Eigen::Vector3d> pole;
  // Aim: the joint-local axis to point at target_position, and optionally a
  // joint-local up axis kept as close as possible to the world up_hint.
  Eigen::Vector3d aim_axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d up_axis = Eigen::Vector3d::UnitY();
  std::optional<Eigen::Vector3d> up_hint;
};

// A range of motion for one joint, on its rotation relative to the rest pose:
// Δ = rest.rotation⁻¹ · local.rotation.
struct JointLimit {
  enum class Kind : unsigned char {
    // Δ = E(order[0], a0)·E(order[1], a1)·E(order[2], a2) (intrinsic, as
    // EulerToQuaternion) with each ai in [min_deg[i], max_deg[i]].
    kEuler,
    // Δ = swing · twist, twist about `axis` within [twist_min_deg,
    // twist_max_deg], swing (perpendicular to the axis) within cone_deg.
    // cone_deg = 0 makes a hinge about `axis` (an elbow or a knee).
    kSwingTwist,
  };
  std::string joint;
  Kind kind = Kind::kEuler;
  std::array<Axis, 3> order = {Axis::kX, Axis::kY, Axis::kZ};
  Eigen::Vector3d min_deg = Eigen::Vector3d::Constant(-180.0);
  Eigen::Vector3d max_deg = Eigen::Vector3d::Constant(180.0);
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // in the joint's rest frame, need not be unit
  double cone_deg = 180.0;
  double twist_min_deg = -180.0;
  double twist_max_deg = 180.0;
};

struct IkOptions {
  // DLS: LM trials, accepted or not; CCD/FABRIK: sweeps over the chain.
  int max_iterations = 200;
  // Reached when every effector is this close. 0 = 1e-4 × the chain length
  // (the longest path from a free joint to an effector point).
  double position_tolerance = 0.0;
  double rotation_tolerance = 1e-4;  // radians
  // DLS: once the targets are reached, slide along the solutions towards the
  // start pose, so that small changes are preferred: 0 = off, 1 = to the
  // nearest solution (a local minimum of ‖q − q_start‖ over the poses that
  // reach the targets; radians, and chain lengths for root translation),
  // between = that fraction of the way per step. Up to 30 more iterations.
  double regularization = 0.0;
  // DLS: when LM stalls short of the target (a local minimum, a singular
  // straight limb against its limit) the best pose is perturbed and
  // solving resumes, at most this many times, within max_iterations.
  int max_restarts = 8;
  uint64_t seed = 1;  // perturbations are deterministic for a given seed
  // Two-bone: the fraction of the limb length over which reaching slows down
  // before full extension, so the limb never snaps straight (0 = exact).
  double softness = 0.0;
};

struct IkRequest {
  IkSolver solver = IkSolver::kDls;
  // Local pose to start from (size = joints); empty = the rest pose.
  std::span<const Trs> start_pose;
  std::vector<IkEffector> effectors;
  std::vector<JointLimit> limits;
  // Which joints may move. By default the joints on each effector's path up
  // to, but excluding, `root` (empty = up to the body root, excluded: it
  // carries the whole body; see body_root_candidates), at most max_chain_depth of them per
  // effector (0 = no cap). The path begins at the effector joint when its
  // rotation matters (a rotation target or a local_offset), else at its
  // parent.
  std::string root;
  int max_chain_depth = 0;
  // Explicit free joints instead of the paths (not combined with root or
  // max_chain_depth).
  std::vector<std::string> free_joints;
  // Per joint, nonzero where it may carry the body (BodyRootCandidates, in
  // ik_body_root.h): each effector's body root is the first candidate on
  // its ancestors from the top (BodyRootAbove); empty = the topmost ancestor.
  std::span<const uint8_t> body_root_candidates;
  // The body root the effectors hang from (the hips) stays where it
  // stands unless freed, so reaching with a hand never swings the legs.
  // free_root_rotation adds it to the free joints (DLS, CCD, FABRIK);
  // free_root_translation lets it translate (DLS).
  bool free_root_rotation = false;
  bool free_root_translation = false;
  IkOptions options;
  // Checked once per iteration; on expiry the best pose so far is returned
  // with stop = kDeadline (the RPC layer maps it to DEADLINE_EXCEEDED).
  std::optional<std::chrono::steady_clock::time_point> deadline;
  std::function<bool()> should_stop;  // true = cancel (stop = kCancelled)
};

struct IkEffectorResidual {
  double position_error = 0.0;  // world units; aim: distance of the target from the aim ray
  double rotation_error = 0.0;  // radians; aim: angle between aim axis and target direction
  bool reached = false;         // within the tolerances
  int body_root = -1;           // the joint carrying the body above the effector (BodyRootAbove)
};

enum class IkStop : unsigned char {
  kConverged,     // every effector reached
  kIterationCap,  // max_iterations used up
  kStalled,       // no further progress (unreachable target, restarts exhausted)
  kDeadline,
  kCancelled,
  kDone,  // a one-shot solver (two-bone, aim) finished short of a target
};

struct IkResult {
  std::vector<Trs> pose;                      // full local pose, size = joints
  std::vector<IkEffectorResidual> residuals;  // one per request effector, same order
  int iterations = 0;
  int restarts = 0;
  bool converged = false;
  IkStop stop = IkStop::kDone;
};

}  // namespace armature
