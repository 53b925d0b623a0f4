// Retargeting's feet option (retarget.cc): where the source plants each foot
// (low and slow), and the target's two-bone IK per leg that pins its foot
// there. Private to the engine.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Geometry>

#include "armature/base/status.h"
#include "armature/engine/anim/body_part_map.h"
#include "armature/engine/kinematics/ik_types.h"
#include "armature/engine/kinematics/ik_workspace.h"
#include "armature/engine/math/transform.h"

namespace armature {

struct FeetPlan {
  struct Leg {
    int hip = -1, knee = -1, foot = -1;
    // The IK's end joint: the foot when it hangs from the knee, else a child of
    // the knee (RobotExpressive's LowerLegL_end; its FootL hangs from the
    // armature root) with the foot's rest position as its local offset.
    int effector = -1;
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
    IkRequest request;
  };
  std::array<Leg, 2> legs;
  double leg_length = 0;  // target, mean of both
  bool Moves(int joint) const {
    for (const Leg& l : legs)
      if (joint == l.hip || joint == l.knee || joint == l.foot) return true;
    return false;
  }
};

// INVALID_ARGUMENT naming the leg and the joint when the target has no
// hip–knee–ankle chain on a side.
Status PlanFeet(const Skeleton& target, const BodyParts& parts, std::span<const Eigen::Affine3d> rest_world,
                FeetPlan& plan);

// Per frame, the planted stretch the source's foot is in (-1: free), and per
// stretch where the target's foot is pinned.
struct FootPins {
  std::vector<int> stretch;
  std::vector<Eigen::Vector3d> pin;
};

// Samples the source's ankles at `times` (sample(t) fills `source_world`),
// finds the planted stretches (height within 10 % of the leg length of the
// clip's lowest, speed under 30 % of the leg length per second, at least
// three frames; stretches less than 0.1 s apart whose ends are within 5 % of
// the leg length of each other are one). One FootPins per leg (left, right).
Status FindPlantedFeet(std::span<const double> times, const BodyParts& source_parts,
                       const std::function<Status(double)>& sample, const std::vector<Eigen::Affine3d>& source_world,
                       std::vector<FootPins>& pins);

// Each stretch's pin: the mean of `natural` (per leg, per frame: where the
// retargeted motion puts the target's foot) over it, so the pin is the
// source's contact, scaled and turned, with the target's own proportions.
void SetPins(const std::vector<std::vector<Eigen::Vector3d>>& natural, std::vector<FootPins>& pins);

// Two-bone IK on each leg of frame `frame` whose source foot is planted: the
// target's foot stays at its stretch's pin. `local` is updated (hip and knee, and the
// foot's local rotation so its world rotation is kept); `world` and
// `rotation` are this frame's, before the IK. When a pin is out of the leg's
// reach, `moved_root` (≥ 0) is lowered until it is in reach, as an animator
// would bend the knees, rather than let the foot slide.
Status PinFeet(const Skeleton& target, FeetPlan& plan, std::vector<FootPins>& pins, size_t frame, int moved_root,
               std::vector<Trs>& local, std::vector<Eigen::Affine3d>& world,
               const std::vector<Eigen::Quaterniond>& rotation, IkWorkspace& workspace, IkResult& result);

}  // namespace armature
