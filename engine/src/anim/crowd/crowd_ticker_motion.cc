// CrowdTicker's motion path, beside the clip path of crowd_ticker.cc: a
// motion character is blended at its motion time, offset + speed·t, not
// wrapped (the layers wrap themselves; ACCUMULATE walks on). With sharing on,
// the time is rounded to the quantum and characters on one motion at one
// rounded time share a blend, as clips do.
#include <algorithm>
#include <cmath>
#include <cstring>
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
  scratch_.resize(10 * max_joints_);
  motion_scratch_.resize(max_joints_);
  clips_.push_back({nullptr, std::move(layout), ClipSamplingContext(), std::move(motion)});
  return static_cast<uint32_t>(clips_.size() - 1);
}

Status CrowdTicker::TickMotion(const CrowdCharacter& c, double time, size_t index, CrowdTick* out, size_t* offset,
                               size_t* samples) {
  ClipEntry& entry = clips_[c.clip];
  const size_t bytes = entry.layout.EncodedSize();
  double t = c.time_offset + c.speed * time;
  // Rounded steps must fit an int64: beyond ~1e15 quanta (centuries) the blend is unshared.
  const bool share = options_.share_quantum > 0 && std::abs(t / options_.share_quantum) < 1e15;
  const int64_t step = share ? std::llround(t / options_.share_quantum) : 0;
  if (share) t = static_cast<double>(step) * options_.share_quantum;
  out->ids[index] = c.id;
  out->clips[index] = c.clip;
  out->clip_times[index] = t;
  uint8_t* dst = out->poses.data() + *offset;
  if (share) {
    const ShareEntry* shared = FindOrInsertShared(c.clip, step, *offset);
    if (shared->offset != *offset) {
      std::memcpy(dst, out->poses.data() + shared->offset, bytes);
      *offset += bytes;
      return Status::Ok();
    }
  }
  std::span<Trs> pose(motion_scratch_.data(), entry.layout.joints);
  ARMATURE_RETURN_IF_ERROR(SampleCrowdMotion(*entry.motion, t, pose));
  EncodePose(entry.layout, pose, dst);
  *offset += bytes;
  ++*samples;
  return Status::Ok();
}

}  // namespace armature
