#include "server/mesh/skinned_mesh_stream_plan.h"

#include <spdlog/spdlog.h>

#include "server/rpc/convert/pose_convert.h"

namespace armature::server {

SkinnedMeshStreamPlan::SkinnedMeshStreamPlan(PartRef<NamedMesh> mesh, MeshClip mesh_clip, SkinningMethod method,
                                             v1::Interpolation interpolation)
    : mesh_(std::move(mesh)), mesh_clip_(std::move(mesh_clip)), interpolation_(interpolation) {
  options_.method = method;
}

Status SkinnedMeshStreamPlan::Fill(uint64_t index, double t, WrapMode wrap, Frame& frame) {
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

void SkinnedMeshStreamPlan::Done(uint64_t frames) const {
  spdlog::debug("skinned stream of '{}' by '{}' done after {} frames", mesh_.part->name, mesh_clip_.clip_ref.part->name,
                frames);
}

}  // namespace armature::server
