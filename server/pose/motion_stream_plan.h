// What StreamClip plays when it gives a motion, without gRPC: frame k is the
// motion at start_time + speed·k/fps, unwrapped (the layers wrap
// themselves), with EXTRACT's root delta. Run by
// PacedStreamReactor<MotionStreamPlan>.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "armature/v1/poses.pb.h"
#include "server/assets/catalog.h"
#include "server/rpc/convert/motion_frames.h"
#include "server/rpc/convert/pose_convert.h"
#include "server/rpc/limits.h"
#include "server/rpc/stream_pacing.h"

namespace armature::server {

class MotionStreamPlan {
 public:
  using Frame = v1::PoseFrame;

  // `request.motion` bound, its joints resolved, the stream's work at
  // `pacing` (validated) checked against --max-stream-work.
  static StatusOr<MotionStreamPlan> Make(const Catalog& catalog, const Limits& limits,
                                         const v1::StreamClipRequest& request, const StreamPacing& pacing);

  double duration() const { return MotionLength(motion_.plan()); }
  Status Fill(uint64_t index, double time, WrapMode wrap, Frame& frame);

 private:
  MotionStreamPlan(StreamPacing pacing, MotionPlan plan, std::string skeleton, v1::Space space,
                   std::vector<int> joints);

  StreamPacing pacing_;
  MotionFrames motion_;
  std::string skeleton_;
  v1::Space space_;
  std::vector<int> joints_;
  PoseWorkspace ws_;
};

}  // namespace armature::server
