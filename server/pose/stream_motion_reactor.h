// Plays a motion as a stream of poses (PoseService.StreamClip with `motion`).
#pragma once

#include <string>
#include <vector>

#include "armature/v1/poses.grpc.pb.h"
#include "server/rpc/motion_frames.h"
#include "server/rpc/paced_stream_reactor.h"
#include "server/rpc/pose_convert.h"

namespace armature::server {

class StreamMotionReactor final : public PacedStreamReactor<v1::PoseFrame> {
 public:
  // `pacing` must already be validated; frame k shows motion time
  // start_time + speed·k/fps, unwrapped (the layers wrap themselves).
  StreamMotionReactor(FrameScheduler& scheduler, StreamPacing pacing, MotionPlan plan, std::string skeleton,
                      v1::Space space, std::vector<int> joints);

 private:
  Status Fill(uint64_t index, double time, WrapMode wrap, v1::PoseFrame& frame) override;

  const StreamPacing pacing_;
  MotionFrames motion_;
  const std::string skeleton_;
  const v1::Space space_;
  const std::vector<int> joints_;
  PoseWorkspace ws_;
};

}  // namespace armature::server
