#include "server/rpc/convert/motion_frames.h"

#include <cmath>
#include <limits>

namespace armature::server {

MotionFrames::MotionFrames(MotionPlan plan) : plan_(std::move(plan)) { workspace_.Resize(plan_); }

double MotionLength(const MotionPlan& plan) {
  const BoundLayer& l = plan.layers[plan.phase_layer >= 0 ? plan.phase_layer : 0];
  if (l.speed == 0) return std::numeric_limits<double>::infinity();
  return l.clip->duration / std::abs(l.speed);
}

Status MotionFrames::Next(double time, std::span<Trs> local, v1::Pose* root_delta) {
  const bool extract = plan_.root_motion == RootMotion::kExtract && root_delta;
  RootDelta delta;
  ARMATURE_RETURN_IF_ERROR((BlendMotionJob{&plan_, time, &workspace_, local, extract ? &delta : nullptr}.Run()));
  if (!extract) return Status::Ok();
  const RootDelta& before = first_ ? delta : previous_;
  const Eigen::Vector3d step = delta.translation - before.translation;
  const Eigen::Quaterniond turn = (delta.rotation * before.rotation.conjugate()).normalized();
  for (double v : step) root_delta->add_translations(static_cast<float>(v));
  for (double v : {turn.w(), turn.x(), turn.y(), turn.z()}) root_delta->add_rotations(static_cast<float>(v));
  previous_ = delta;
  first_ = false;
  return Status::Ok();
}

}  // namespace armature::server
