// Rigs for IK tests and benchmarks, built in code: a skeleton with the bone
// offsets of CMU subject 01 (the hierarchy of cmu_01_01.bvh, in its inches),
// human-like limits for its limbs, and a 7-DOF arm with the proportions of a
// KUKA iiwa (metres). Reachable targets are the forward kinematics of random
// poses within the limits. Shared by tests/engine/ik_*_test.cc and
// bench/ik*_bench.cc; header-only so both binaries take it as is.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "armature/engine/kinematics/fk.h"
#include "armature/engine/kinematics/joint_limits.h"
#include "armature/engine/kinematics/ik_types.h"
#include "armature/engine/anim/skeleton.h"

namespace armature::ik_rigs {

struct JointSpec {
  const char* name;
  const char* parent;  // nullptr for the root
  Eigen::Vector3d offset;
};

inline Skeleton BuildSkeleton(const std::vector<JointSpec>& specs) {
  Skeleton s;
  for (const JointSpec& j : specs) {
    s.names.push_back(j.name);
    s.parents.push_back(j.parent ? s.Find(j.parent) : -1);
    Trs rest;
    rest.translation = j.offset;
    s.rest.push_back(rest);
    s.channels.emplace_back();
    s.end_sites.emplace_back();
  }
  return s;
}

// The CMU hierarchy (cmu_01_01.bvh), offsets in its units.
inline Skeleton CmuLikeSkeleton() {
  return BuildSkeleton({
      {"Hips", nullptr, {0, 0, 0}},
      {"LHipJoint", "Hips", {0, 0, 0}},
      {"LeftUpLeg", "LHipJoint", {1.36306, -1.79463, 0.83929}},
      {"LeftLeg", "LeftUpLeg", {2.44811, -6.72613, 0}},
      {"LeftFoot", "LeftLeg", {2.56220, -7.03959, 0}},
      {"LeftToeBase", "LeftFoot", {0.15764, -0.43311, 2.32255}},
      {"RHipJoint", "Hips", {0, 0, 0}},
      {"RightUpLeg", "RHipJoint", {-1.30552, -1.79463, 0.83929}},
      {"RightLeg", "RightUpLeg", {-2.54253, -6.98555, 0}},
      {"RightFoot", "RightLeg", {-2.56826, -7.05623, 0}},
      {"RightToeBase", "RightFoot", {-0.16473, -0.45259, 2.36315}},
      {"LowerBack", "Hips", {0, 0, 0}},
      {"Spine", "LowerBack", {0.02827, 2.03559, -0.19338}},
      {"Spine1", "Spine", {0.05672, 2.04885, -0.04275}},
      {"Neck", "Spine1", {0, 0, 0}},
      {"Neck1", "Neck", {-0.05417, 1.74624, 0.17202}},
      {"Head", "Neck1", {0.10407, 1.76136, -0.12397}},
      {"LeftShoulder", "Spine1", {0, 0, 0}},
      {"LeftArm", "LeftShoulder", {3.36241, 1.20089, -0.31121}},
      {"LeftForeArm", "LeftArm", {4.98300, 0, 0}},
      {"LeftHand", "LeftForeArm", {3.48356, 0, 0}},
      {"LeftFingerBase", "LeftHand", {0, 0, 0}},
      {"LFingers", "LeftFingerBase", {0.71526, 0, 0}},
      {"LThumb", "LeftHand", {0, 0, 0}},
      {"RightShoulder", "Spine1", {0, 0, 0}},
      {"RightArm", "RightShoulder", {-3.13660, 1.37405, -0.40465}},
      {"RightForeArm", "RightArm", {-5.24190, 0, 0}},
      {"RightHand", "RightForeArm", {-3.44417, 0, 0}},
      {"RightFingerBase", "RightHand", {0, 0, 0}},
      {"RFingers", "RightFingerBase", {-0.62253, 0, 0}},
      {"RThumb", "RightHand", {0, 0, 0}},
  });
}

inline JointLimit EulerLimit(const char* joint, Eigen::Vector3d min_deg, Eigen::Vector3d max_deg) {
  JointLimit l;
  l.joint = joint;
  l.kind = JointLimit::Kind::kEuler;
  l.order = {Axis::kZ, Axis::kY, Axis::kX};  // the CMU channel order
  l.min_deg = min_deg;
  l.max_deg = max_deg;
  return l;
}

inline JointLimit SwingTwistLimit(const char* joint, Eigen::Vector3d axis, double cone_deg, double twist_min_deg,
                                  double twist_max_deg) {
  JointLimit l;
  l.joint = joint;
  l.kind = JointLimit::Kind::kSwingTwist;
  l.axis = axis;
  l.cone_deg = cone_deg;
  l.twist_min_deg = twist_min_deg;
  l.twist_max_deg = twist_max_deg;
  return l;
}

inline JointLimit HingeLimit(const char* joint, Eigen::Vector3d axis, double min_deg, double max_deg) {
  return SwingTwistLimit(joint, axis, 0.0, min_deg, max_deg);
}

// Human-like ranges for the CMU limbs and spine. The character faces +Z, its
// arms point along ±X and its legs down −Y in the rest pose.
inline std::vector<JointLimit> CmuLimits() {
  using V = Eigen::Vector3d;
  return {
      EulerLimit("LeftArm", V(-80, -90, -80), V(80, 30, 80)),
      HingeLimit("LeftForeArm", V(0, -1, 0), 0, 145),  // flexes the forearm forward (+Z)
      EulerLimit("LeftHand", V(-70, -30, -80), V(70, 30, 80)),
      EulerLimit("RightArm", V(-80, -30, -80), V(80, 90, 80)),
      HingeLimit("RightForeArm", V(0, 1, 0), 0, 145),
      EulerLimit("RightHand", V(-70, -30, -80), V(70, 30, 80)),
      SwingTwistLimit("LeftUpLeg", V(2.44811, -6.72613, 0), 75, -40, 40),  // cone about the thigh
      HingeLimit("LeftLeg", V(1, 0, 0), 0, 150),                           // flexes the shin backward (−Z)
      EulerLimit("LeftFoot", V(-30, -30, -45), V(30, 30, 45)),
      SwingTwistLimit("RightUpLeg", V(-2.54253, -6.98555, 0), 75, -40, 40),
      HingeLimit("RightLeg", V(1, 0, 0), 0, 150),
      EulerLimit("RightFoot", V(-30, -30, -45), V(30, 30, 45)),
      EulerLimit("LowerBack", V(-20, -30, -20), V(20, 30, 40)),
      EulerLimit("Spine", V(-15, -20, -15), V(15, 20, 30)),
      EulerLimit("Spine1", V(-15, -20, -15), V(15, 20, 30)),
      EulerLimit("Neck1", V(-30, -60, -40), V(30, 60, 40)),
      EulerLimit("Head", V(-20, -30, -30), V(20, 30, 30)),
  };
}

// A 7-DOF serial arm with alternating Z/Y hinges (iiwa-like, metres); the
// effector is the flange, 0.126 m beyond the last hinge.
inline Skeleton SevenDofSkeleton() {
  return BuildSkeleton({
      {"base", nullptr, {0, 0, 0}},
      {"j1", "base", {0, 0, 0.1575}},
      {"j2", "j1", {0, 0, 0.2025}},
      {"j3", "j2", {0, 0, 0.2045}},
      {"j4", "j3", {0, 0, 0.2155}},
      {"j5", "j4", {0, 0, 0.1845}},
      {"j6", "j5", {0, 0, 0.2155}},
      {"j7", "j6", {0, 0, 0.0810}},
  });
}
inline const Eigen::Vector3d kSevenDofFlange(0, 0, 0.126);

inline std::vector<JointLimit> SevenDofLimits() {
  using V = Eigen::Vector3d;
  return {
      HingeLimit("j1", V::UnitZ(), -170, 170), HingeLimit("j2", V::UnitY(), -120, 120),
      HingeLimit("j3", V::UnitZ(), -170, 170), HingeLimit("j4", -V::UnitY(), -120, 120),
      HingeLimit("j5", V::UnitZ(), -170, 170), HingeLimit("j6", V::UnitY(), -120, 120),
      HingeLimit("j7", V::UnitZ(), -175, 175),
  };
}

// One benchmark/test problem: a chain of `joints` (top first) on `skeleton`
// under `root`, an effector at `effector` + `offset`, with a rotation target
// or not.
struct LimbCase {
  std::string name;
  Skeleton skeleton;
  std::vector<JointLimit> limits;
  std::vector<std::string> joints;  // the free joints, top first
  std::string root;                 // excluded parent of joints[0]
  std::string effector;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  bool with_rotation = false;
  double chain_length = 0;  // from joints[0] to the effector point, summed bone lengths
};

inline double PathLength(const Skeleton& s, const std::string& top, const std::string& effector,
                         const Eigen::Vector3d& offset) {
  double length = offset.norm();
  for (int j = s.Find(effector); j != s.Find(top); j = s.parents[j]) length += s.rest[j].translation.norm();
  return length;
}

inline LimbCase MakeCase(std::string name, Skeleton skeleton, std::vector<JointLimit> limits,
                         std::vector<std::string> joints, std::string root, std::string effector,
                         Eigen::Vector3d offset, bool with_rotation) {
  LimbCase c{std::move(name),
             std::move(skeleton),
             std::move(limits),
             std::move(joints),
             std::move(root),
             std::move(effector),
             offset,
             with_rotation,
             0.0};
  c.chain_length = PathLength(c.skeleton, c.joints.front(), c.effector, c.offset);
  return c;
}

// The CMU limbs (shoulder: Euler ball, elbow: hinge, wrist: Euler; hip:
// cone, knee: hinge, ankle: Euler) and the 7-DOF arm, each reaching a
// position (3-D target) or a pose (position and rotation, 6-D):
//   cmu_left_arm_reach   shoulder + elbow → wrist position         4 DOF, 3-D
//   cmu_left_arm_pose    shoulder + elbow + wrist → hand pose      7 DOF, 6-D
//   cmu_right_leg_reach  hip + knee → ankle position               4 DOF, 3-D
//   cmu_right_leg_pose   hip + knee + ankle → foot pose            7 DOF, 6-D
//   seven_dof_pose       seven hinges → flange pose                7 DOF, 6-D
inline std::vector<LimbCase> StandardCases() {
  const Eigen::Vector3d none = Eigen::Vector3d::Zero();
  return {
      MakeCase("cmu_left_arm_reach", CmuLikeSkeleton(), CmuLimits(), {"LeftArm", "LeftForeArm"}, "LeftShoulder",
               "LeftHand", none, false),
      MakeCase("cmu_left_arm_pose", CmuLikeSkeleton(), CmuLimits(), {"LeftArm", "LeftForeArm", "LeftHand"},
               "LeftShoulder", "LeftHand", none, true),
      MakeCase("cmu_right_leg_reach", CmuLikeSkeleton(), CmuLimits(), {"RightUpLeg", "RightLeg"}, "RHipJoint",
               "RightFoot", none, false),
      MakeCase("cmu_right_leg_pose", CmuLikeSkeleton(), CmuLimits(), {"RightUpLeg", "RightLeg", "RightFoot"},
               "RHipJoint", "RightFoot", none, true),
      MakeCase("seven_dof_pose", SevenDofSkeleton(), SevenDofLimits(), {"j1", "j2", "j3", "j4", "j5", "j6", "j7"},
               "base", "j7", kSevenDofFlange, true),
  };
}

inline LimbCase StandardCase(const std::string& name) {
  for (LimbCase& c : StandardCases())
    if (c.name == name) return c;
  return {};
}

inline const JointLimit* FindLimit(const std::vector<JointLimit>& limits, const std::string& joint) {
  for (const JointLimit& l : limits)
    if (l.joint == joint) return &l;
  return nullptr;
}

// The rest pose with each chain joint turned to a random rotation inside its limit.
inline std::vector<Trs> RandomPose(const LimbCase& c, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Trs> pose = c.skeleton.rest;
  for (const std::string& name : c.joints) {
    const int j = c.skeleton.Find(name);
    const Eigen::Vector3d r(u(rng), u(rng), u(rng));
    pose[j].rotation = c.skeleton.rest[j].rotation * SampleWithinLimit(*FindLimit(c.limits, name), r);
  }
  return pose;
}

// World positions and rotations of a pose, by the engine's forward kinematics.
struct World {
  std::vector<Eigen::Affine3d> transform;
  std::vector<Eigen::Quaterniond> rotation;
  Eigen::Vector3d Position(const Skeleton& s, const std::string& joint) const {
    return transform[s.Find(joint)].translation();
  }
};

inline World WorldOf(const Skeleton& s, const std::vector<Trs>& pose) {
  World w;
  w.transform.resize(pose.size());
  w.rotation.resize(pose.size());
  ComputeWorld(s, pose, w.transform, w.rotation);
  return w;
}

struct Target {
  Eigen::Vector3d position;
  Eigen::Quaterniond rotation;
};

inline Target TargetOf(const LimbCase& c, const std::vector<Trs>& pose) {
  const World w = WorldOf(c.skeleton, pose);
  const int e = c.skeleton.Find(c.effector);
  return {w.transform[e] * c.offset, w.rotation[e]};
}

// Whether every joint of `pose` with a limit is inside it (to `slack_rad`).
inline bool WithinLimits(const Skeleton& s, const std::vector<JointLimit>& limits, const std::vector<Trs>& pose,
                         double slack_rad = 1e-6) {
  for (const JointLimit& l : limits) {
    const int j = s.Find(l.joint);
    if (!WithinLimit(l, s.rest[j].rotation.conjugate() * pose[j].rotation, slack_rad)) return false;
  }
  return true;
}

// A request with one effector on `joint`.
inline IkRequest OneEffector(IkSolver solver, const std::string& joint, std::optional<Eigen::Vector3d> position,
                             std::optional<Eigen::Quaterniond> rotation = std::nullopt) {
  IkRequest r;
  r.solver = solver;
  IkEffector e;
  e.joint = joint;
  e.target_position = position;
  e.target_rotation = rotation;
  r.effectors.push_back(e);
  return r;
}

// A DLS request for `target` from the rest pose, stopping at half the
// success threshold (1e-3 × chain length, 1e-3 rad).
inline IkRequest RequestFor(const LimbCase& c, const Target& target) {
  IkRequest r = OneEffector(IkSolver::kDls, c.effector, target.position,
                            c.with_rotation ? std::optional(target.rotation) : std::nullopt);
  r.effectors[0].local_offset = c.offset;
  r.limits = c.limits;
  r.root = c.root;
  r.options.position_tolerance = 0.5e-3 * c.chain_length;
  r.options.rotation_tolerance = 0.5e-3;
  return r;
}

// Spine and both arms of the CMU rig, for two-handed reaching from the hips.
inline LimbCase UpperBodyCase() {
  return MakeCase("upper_body", CmuLikeSkeleton(), CmuLimits(),
                  {"LowerBack", "Spine", "Spine1", "LeftArm", "LeftForeArm", "RightArm", "RightForeArm"}, "Hips",
                  "LeftHand", Eigen::Vector3d::Zero(), false);
}

// Both hands to where `goal` (a pose of UpperBodyCase) puts them, within
// `tolerance`, through the spine and arms.
inline IkRequest TwoHandsRequest(const LimbCase& body, const std::vector<Trs>& goal, double tolerance) {
  const World w = WorldOf(body.skeleton, goal);
  IkRequest r = OneEffector(IkSolver::kDls, "LeftHand", w.Position(body.skeleton, "LeftHand"));
  r.effectors.push_back(OneEffector(IkSolver::kDls, "RightHand", w.Position(body.skeleton, "RightHand")).effectors[0]);
  r.limits = body.limits;
  r.root = body.root;
  r.options.position_tolerance = tolerance;
  return r;
}

inline bool Reached(const LimbCase& c, double position_error, double rotation_error) {
  return position_error <= 1e-3 * c.chain_length && (!c.with_rotation || rotation_error <= 1e-3);
}

}  // namespace armature::ik_rigs
