// What StreamSkinnedMesh plays when it names a clip, without gRPC: one
// skinned mesh per frame, paced like StreamClip. Run by
// PacedStreamReactor<SkinnedMeshStreamPlan>.
#pragma once

#include <cstdint>

#include "armature/engine/mesh/skinning.h"
#include "armature/v1/meshes.pb.h"
#include "server/assets/catalog.h"
#include "server/mesh/mesh_convert.h"

namespace armature::server {

class SkinnedMeshStreamPlan {
 public:
  using Frame = v1::SkinnedMeshFrame;

  // The mesh and clip are held for the stream's life.
  SkinnedMeshStreamPlan(PartRef<NamedMesh> mesh, MeshClip mesh_clip, SkinningMethod method,
                        v1::Interpolation interpolation);

  double duration() const { return mesh_clip_.clip_ref.part->runtime->duration; }
  Status Fill(uint64_t index, double time, WrapMode wrap, Frame& frame);
  void Done(uint64_t frames) const;

 private:
  PartRef<NamedMesh> mesh_;
  MeshClip mesh_clip_;
  v1::Interpolation interpolation_;
  SkinningOptions options_;
  SkinningWorkspace ws_;
};

}  // namespace armature::server
