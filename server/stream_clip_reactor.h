// Plays a clip as a stream of poses (PoseService.StreamClip).
#pragma once

#include <vector>

#include "armature/v1/poses.grpc.pb.h"
#include "server/asset_store.h"
#include "server/paced_stream_reactor.h"
#include "server/proto_convert.h"

namespace armature::server {

class StreamClipReactor final : public PacedStreamReactor<v1::PoseFrame> {
 public:
  // `request` must already be validated; `clip` is held for the stream's life.
  StreamClipReactor(FrameScheduler& scheduler, PartRef<NamedClip> clip, v1::StreamClipRequest request,
                    std::vector<int> joints);

 private:
  Status Fill(uint64_t index, double time, WrapMode wrap, v1::PoseFrame& frame) override;
  void OnStreamDone(uint64_t frames) override;

  PartRef<NamedClip> clip_;
  v1::StreamClipRequest request_;
  std::vector<int> joints_;
  PoseWorkspace ws_;
};

// The pacing fields of a validated StreamClipRequest.
StreamPacing PacingOf(const v1::StreamClipRequest& request);

}  // namespace armature::server
