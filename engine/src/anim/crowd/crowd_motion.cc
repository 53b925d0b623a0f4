#include "armature/engine/anim/crowd/crowd_motion.h"

#include <string>
#include <vector>

namespace armature {
namespace {

// CompressedClip::animated_parts bits.
constexpr uint8_t kTranslationPart = 2, kScalePart = 4;

// The joints where some layer acting there animates `part`: those may vary
// over time; a joint no layer animates keeps one value (rest, or a blend of
// constants), which the base pose holds.
std::vector<uint16_t> AnimatedJoints(const MotionPlan& plan, uint8_t part) {
  std::vector<uint16_t> joints;
  for (size_t j = 0; j + 1 < plan.joint_begin.size(); ++j) {
    bool animated = part == kTranslationPart && static_cast<int>(j) == plan.root;
    for (uint32_t k = plan.joint_begin[j]; k < plan.joint_begin[j + 1] && !animated; ++k)
      animated = (plan.joint_layers[k].parts & part) != 0;
    if (animated) joints.push_back(static_cast<uint16_t>(j));
  }
  return joints;
}

}  // namespace

StatusOr<PoseLayout> LayoutOfMotion(const MotionPlan& plan) {
  if (!plan.skeleton) return Status::InvalidArgument("pose layout: the motion has no skeleton");
  if (plan.skeleton->size() > 65535)
    return Status::InvalidArgument("pose layout: " + std::to_string(plan.skeleton->size()) + " joints, at most 65535");
  PoseLayout layout;
  layout.joints = static_cast<uint32_t>(plan.skeleton->size());
  layout.translated = AnimatedJoints(plan, kTranslationPart);
  layout.scaled = AnimatedJoints(plan, kScalePart);
  layout.base.resize(layout.joints);
  MotionWorkspace workspace;
  workspace.Resize(plan);
  ARMATURE_RETURN_IF_ERROR((BlendMotionJob{&plan, 0.0, &workspace, layout.base}.Run()));
  return layout;
}

Status SampleCrowdMotion(CrowdMotion& motion, double time, std::span<Trs> pose) {
  return BlendMotionJob{motion.plan.get(), time, &motion.workspace, pose}.Run();
}

}  // namespace armature
