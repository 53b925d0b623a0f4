// What StreamSkinnedMesh plays when it gives a motion, without gRPC: one
// skinned mesh per frame, paced like StreamClip's motion (unwrapped motion
// time; EXTRACT's root delta per frame). Run by
// PacedStreamReactor<SkinnedMotionStreamPlan>.
#pragma once

#include <cstdint>
#include <vector>

#include "armature/engine/mesh/skinning.h"
#include "armature/v1/meshes.pb.h"
#include "server/assets/catalog.h"
#include "server/rpc/convert/motion_frames.h"
#include "server/rpc/stream_pacing.h"

namespace armature::server {

class SkinnedMotionStreamPlan {
 public:
  using Frame = v1::SkinnedMeshFrame;

  // `pacing` must be validated: frame k shows motion time start_time + speed·k/fps.
  SkinnedMotionStreamPlan(StreamPacing pacing, PartRef<NamedMesh> mesh, MotionPlan plan, SkinningMethod method);

  double duration() const { return MotionLength(motion_.plan()); }
  Status Fill(uint64_t index, double time, WrapMode wrap, Frame& frame);

 private:
  StreamPacing pacing_;
  PartRef<NamedMesh> mesh_;
  MotionFrames motion_;
  std::vector<Trs> local_;
  SkinningOptions options_;
  SkinningWorkspace ws_;
};

}  // namespace armature::server
