#include "server/mesh/skinned_mesh_stream_reactor.h"

#include <spdlog/spdlog.h>

#include "server/mesh/mesh_convert.h"
#include "server/rpc/pose_convert.h"

namespace armature::server {

StreamSkinnedMeshReactor::StreamSkinnedMeshReactor(FrameScheduler& scheduler, StreamPacing pacing,
                                                   PartRef<NamedMesh> mesh, MeshClip mesh_clip,
                                                   SkinningMethod method, v1::Interpolation interpolation)
    : PacedStreamReactor(scheduler, pacing, mesh_clip.clip_ref.part->clip->duration), mesh_(std::move(mesh)),
      mesh_clip_(std::move(mesh_clip)), interpolation_(interpolation) {
  options_.method = method;
  Start();
}

Status StreamSkinnedMeshReactor::Fill(uint64_t index, double t, WrapMode wrap, v1::SkinnedMeshFrame& frame) {
  SampleOptions sample;
  sample.interpolation = server::FromProto(interpolation_);
  sample.wrap = wrap;
  const Mesh& mesh = *mesh_.part->mesh;
  auto [positions, normals] = OutputsOf(mesh, &frame);
  ARMATURE_RETURN_IF_ERROR(SkinByClip(mesh, mesh_clip_, t, sample, options_, positions, normals, ws_));
  frame.set_index(index);
  frame.set_time(t);
  return Status::Ok();
}

void StreamSkinnedMeshReactor::OnStreamDone(uint64_t frames) {
  spdlog::debug("skinned stream of '{}' by '{}' done after {} frames", mesh_.part->name,
                mesh_clip_.clip_ref.part->name, frames);
}

}  // namespace armature::server
