#include "server/mesh/skinned_mesh_stream_reactor.h"

#include <spdlog/spdlog.h>

#include "server/mesh/mesh_convert.h"
#include "server/rpc/pose_convert.h"

namespace armature::server {

StreamSkinnedMeshReactor::StreamSkinnedMeshReactor(FrameScheduler& scheduler, StreamPacing pacing,
                                                   PartRef<NamedMesh> mesh, MeshClip clip,
                                                   SkinningMethod method, v1::Interpolation interpolation)
    : PacedStreamReactor(scheduler, pacing, clip.clip.part->clip->duration), mesh_(std::move(mesh)),
      clip_(std::move(clip)), interpolation_(interpolation) {
  options_.method = method;
  Start();
}

Status StreamSkinnedMeshReactor::Fill(uint64_t index, double t, WrapMode wrap, v1::SkinnedMeshFrame& frame) {
  SampleOptions sample;
  sample.interpolation = server::FromProto(interpolation_);
  sample.wrap = wrap;
  const Mesh& mesh = *mesh_.part->mesh;
  auto [positions, normals] = OutputsOf(mesh, &frame);
  ARMATURE_RETURN_IF_ERROR(SkinByClip(mesh, clip_, t, sample, options_, positions, normals, ws_));
  frame.set_index(index);
  frame.set_time(t);
  return Status::Ok();
}

void StreamSkinnedMeshReactor::OnStreamDone(uint64_t frames) {
  spdlog::debug("skinned stream of '{}' by '{}' done after {} frames", mesh_.part->name, clip_.clip.part->name, frames);
}

}  // namespace armature::server
