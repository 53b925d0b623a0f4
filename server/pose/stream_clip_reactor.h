// Plays a clip as a stream of poses (PoseService.StreamClip).
#pragma once

#include <vector>

#include "armature/v1/poses.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/paced_stream_reactor.h"
#include "server/rpc/pose_convert.h"

namespace armature::server {

class StreamClipReactor final : public PacedStreamReactor<v1::PoseFrame> {
 public:
  // `pacing` must already be validated (ValidatePacing); `request` gives the
  // space and interpolation; `clip` is held for the stream's life.
  StreamClipReactor(FrameScheduler& scheduler, StreamPacing pacing, PartRef<NamedClip> clip,
                    v1::StreamClipRequest request, std::vector<int> joints);

 private:
  Status Fill(uint64_t index, double time, WrapMode wrap, v1::PoseFrame& frame) override;
  void OnStreamDone(uint64_t frames) override;

  PartRef<NamedClip> clip_;
  v1::StreamClipRequest request_;
  std::vector<int> joints_;
  PoseWorkspace ws_;
};

}  // namespace armature::server
