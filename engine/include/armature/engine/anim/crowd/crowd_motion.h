// A crowd character on a motion (issue 31): the motion is bound once
// (BindMotion), and each update blends it with BlendMotionJob at the
// character's motion time, offset + speed·t (not wrapped: layers wrap
// themselves). Its poses go on the wire like a clip's, in a layout of their
// own: a translation for each joint whose translation any layer's clip
// animates (and the root-motion joint), likewise scales; the rest is the
// motion's pose at time 0.
#pragma once

#include <memory>
#include <span>

#include "armature/base/status.h"
#include "armature/engine/anim/crowd/pose_encoding.h"
#include "armature/engine/anim/motion.h"

namespace armature {

// A bound motion a crowd's characters play, with its blend scratch space.
struct CrowdMotion {
  std::shared_ptr<const MotionPlan> plan;
  MotionWorkspace workspace;
};

// The layout of a bound motion's poses (blends the motion once at time 0).
StatusOr<PoseLayout> LayoutOfMotion(const MotionPlan& plan);

// Blends `motion` at motion time `time` into `pose` (one per skeleton joint); no allocation.
Status SampleCrowdMotion(CrowdMotion& motion, double time, std::span<Trs> pose);

}  // namespace armature
