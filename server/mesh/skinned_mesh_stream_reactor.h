// StreamSkinnedMesh: plays a clip on a mesh, one skinned mesh per frame,
// paced like StreamClip.
#pragma once

#include <cstdint>

#include "armature/engine/mesh/skinning.h"
#include "armature/v1/meshes.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/mesh/mesh_convert.h"
#include "server/rpc/paced_stream_reactor.h"

namespace armature::server {

class StreamSkinnedMeshReactor final : public PacedStreamReactor<v1::SkinnedMeshFrame> {
 public:
  StreamSkinnedMeshReactor(FrameScheduler& scheduler, StreamPacing pacing, PartRef<NamedMesh> mesh,
                           MeshClip mesh_clip, SkinningMethod method, v1::Interpolation interpolation);

 private:
  Status Fill(uint64_t index, double t, WrapMode wrap, v1::SkinnedMeshFrame& frame) override;
  void OnStreamDone(uint64_t frames) override;

  PartRef<NamedMesh> mesh_;
  MeshClip mesh_clip_;
  v1::Interpolation interpolation_;
  SkinningOptions options_;
  SkinningWorkspace ws_;
};

}  // namespace armature::server
