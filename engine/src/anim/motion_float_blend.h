// Internal: the motion blend's float lanes (FloatBlendPlan, anim/motion.h):
// bound once by BindMotion, run by BlendMotionJob.
#pragma once

#include <span>

#include "armature/engine/anim/motion.h"

namespace armature::motion_internal {

// After joint_layers are indexed (and the root chosen): picks the float
// joints and layers, and groups the float joints' properties four by four.
void BindFloatBlend(MotionPlan& plan);

// The float joints' transforms from the layers' float lanes in `workspace`
// (sampled at this time); every other joint of `output` is left as it was.
void BlendFloatJoints(const MotionPlan& plan, const MotionWorkspace& workspace, std::span<Trs> output);

}  // namespace armature::motion_internal
