// A bound motion played frame after frame, as the motion streams play it
// (StreamClip and StreamSkinnedMesh with a motion): each frame's local pose
// and, with rootMotion EXTRACT, the root's motion since the previous frame.
#pragma once

#include <cstdint>
#include <span>

#include "armature/engine/anim/motion.h"
#include "armature/v1/types.pb.h"
#include "server/rpc/stream_pacing.h"

namespace armature::server {

// The motion's length for a stream that does not loop: its first override
// layer's (else its first layer's) clip duration over |speed|.
double MotionLength(const MotionPlan& plan);

// Motion time of stream frame `index`: start_time + speed·index/fps, as the
// paced stream computes it, but not wrapped (a motion's layers wrap themselves).
inline double MotionStreamTime(const StreamPacing& pacing, uint64_t index) {
  return pacing.start_time + pacing.speed * (static_cast<double>(index) / pacing.fps);
}

class MotionFrames {
 public:
  explicit MotionFrames(MotionPlan plan);

  const MotionPlan& plan() const { return plan_; }
  const Skeleton& skeleton() const { return *plan_.skeleton; }
  bool extracts_root() const { return plan_.root_motion == RootMotion::kExtract; }

  // Blends the motion at `time` into `local` (one Trs per skeleton joint).
  // With EXTRACT and a `root_delta`, writes there the root's motion since the
  // previous call (zero on the first): translations T − T_prev, rotations
  // R·R_prev⁻¹ (w, x, y, z), of the RootDelta the engine takes out of the pose.
  Status Next(double time, std::span<Trs> local, v1::Pose* root_delta);

 private:
  MotionPlan plan_;
  MotionWorkspace workspace_;
  RootDelta previous_;
  bool first_ = true;
};

}  // namespace armature::server
