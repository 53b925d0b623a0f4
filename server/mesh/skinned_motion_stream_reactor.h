// StreamSkinnedMesh with a motion: one skinned mesh per frame, paced like
// StreamClip's motion (unwrapped motion time; EXTRACT's root delta per frame).
#pragma once

#include <cstdint>
#include <vector>

#include "armature/engine/mesh/skinning.h"
#include "armature/v1/meshes.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/motion_frames.h"
#include "server/rpc/paced_stream_reactor.h"

namespace armature::server {

class SkinnedMotionStreamReactor final : public PacedStreamReactor<v1::SkinnedMeshFrame> {
 public:
  SkinnedMotionStreamReactor(FrameScheduler& scheduler, StreamPacing pacing, PartRef<NamedMesh> mesh,
                             MotionPlan plan, SkinningMethod method);

 private:
  Status Fill(uint64_t index, double t, WrapMode wrap, v1::SkinnedMeshFrame& frame) override;

  const StreamPacing pacing_;
  PartRef<NamedMesh> mesh_;
  MotionFrames motion_;
  std::vector<Trs> local_;
  SkinningOptions options_;
  SkinningWorkspace ws_;
};

}  // namespace armature::server
