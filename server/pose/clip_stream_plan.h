// What StreamClip plays when it names a clip, without gRPC: frame k is the
// clip sampled at the paced time, the listed joints packed in the asked
// space. Run by PacedStreamReactor<ClipStreamPlan>.
#pragma once

#include <cstdint>
#include <vector>

#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/v1/poses.pb.h"
#include "server/assets/catalog.h"
#include "server/rpc/convert/pose_convert.h"
#include "server/rpc/limits.h"
#include "server/rpc/stream_pacing.h"

namespace armature::server {

class ClipStreamPlan {
 public:
  using Frame = v1::PoseFrame;

  // `request.clip` looked up, its joints resolved, the stream's work at
  // `pacing` (validated) checked against --max-stream-work. The clip is
  // held for the stream's life.
  static StatusOr<ClipStreamPlan> Make(const Catalog& catalog, const Limits& limits,
                                       const v1::StreamClipRequest& request, const StreamPacing& pacing);

  double duration() const;
  Status Fill(uint64_t index, double time, WrapMode wrap, Frame& frame);
  void Done(uint64_t frames) const;

 private:
  ClipStreamPlan(PartRef<NamedClip> clip, v1::Interpolation interpolation, v1::Space space, std::vector<int> joints);

  PartRef<NamedClip> clip_;
  v1::Interpolation interpolation_;
  v1::Space space_;
  std::vector<int> joints_;
  PoseWorkspace ws_;
  ClipSamplingContext context_;  // sequential frames read each segment's header once
};

}  // namespace armature::server
