#include "server/mesh/skinned_motion_stream_plan.h"

#include "server/mesh/mesh_convert.h"

namespace armature::server {

SkinnedMotionStreamPlan::SkinnedMotionStreamPlan(StreamPacing pacing, PartRef<NamedMesh> mesh, MotionPlan plan,
                                                 SkinningMethod method)
    : pacing_(pacing), mesh_(std::move(mesh)), motion_(std::move(plan)) {
  local_.resize(motion_.skeleton().size());
  options_.method = method;
}

Status SkinnedMotionStreamPlan::Fill(uint64_t index, double, WrapMode, Frame& frame) {
  const double t = MotionStreamTime(pacing_, index);  // not wrapped: the layers wrap themselves
  ARMATURE_RETURN_IF_ERROR(motion_.Next(t, local_, motion_.extracts_root() ? frame.mutable_root_delta() : nullptr));
  const Mesh& mesh = *mesh_.part->mesh;
  auto [positions, normals] = OutputsOf(mesh, &frame);
  ARMATURE_RETURN_IF_ERROR(SkinPose(mesh, motion_.skeleton(), local_, options_, positions, normals, ws_));
  frame.set_index(index);
  frame.set_time(t);
  return Status::Ok();
}

}  // namespace armature::server
