// CrowdTicker's motion path, beside the clip path of crowd_ticker.cc: a
// motion character is blended at its own motion time each update. Motions
// share no samples: their times are not wrapped, and a motion crowd is rarely
// large enough for sharing to pay.
#include <algorithm>
#include <utility>

#include "armature/engine/anim/crowd/crowd_ticker.h"

namespace armature {

StatusOr<uint32_t> CrowdTicker::AddMotion(std::shared_ptr<const MotionPlan> plan) {
  if (!plan) return Status::InvalidArgument("crowd: no motion");
  for (size_t i = 0; i < clips_.size(); ++i)
    if (clips_[i].motion && clips_[i].motion->plan == plan) return static_cast<uint32_t>(i);
  ARMATURE_ASSIGN_OR_RETURN(PoseLayout layout, LayoutOfMotion(*plan));
  auto motion = std::make_unique<CrowdMotion>();
  motion->workspace.Resize(*plan);
  motion->plan = std::move(plan);
  max_joints_ = std::max<size_t>(max_joints_, layout.joints);
  max_pose_bytes_ = std::max(max_pose_bytes_, layout.EncodedSize());
  scratch_.resize(max_joints_);
  clips_.push_back({nullptr, std::move(layout), ClipSamplingContext(), std::move(motion)});
  return static_cast<uint32_t>(clips_.size() - 1);
}

Status CrowdTicker::TickMotion(const CrowdCharacter& c, double time, size_t index, CrowdTick* out, size_t* offset) {
  ClipEntry& entry = clips_[c.clip];
  const double t = c.time_offset + c.speed * time;
  out->ids[index] = c.id;
  out->clips[index] = c.clip;
  out->clip_times[index] = t;
  std::span<Trs> pose(scratch_.data(), entry.layout.joints);
  ARMATURE_RETURN_IF_ERROR(SampleCrowdMotion(*entry.motion, t, pose));
  EncodePose(entry.layout, pose, out->poses.data() + *offset);
  *offset += entry.layout.EncodedSize();
  return Status::Ok();
}

}  // namespace armature
