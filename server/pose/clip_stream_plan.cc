#include "server/pose/clip_stream_plan.h"

#include <spdlog/spdlog.h>

#include "server/rpc/request_validation.h"
#include "server/rpc/work/work_budget.h"

namespace armature::server {

StatusOr<ClipStreamPlan> ClipStreamPlan::Make(const Catalog& catalog, const Limits& limits,
                                              const v1::StreamClipRequest& request, const StreamPacing& pacing) {
  ARMATURE_ASSIGN_OR_RETURN(PartRef<NamedClip> ref, catalog.FindClip(request.clip()));
  const Skeleton& skeleton = *ref.part->runtime->skeleton;
  ARMATURE_ASSIGN_OR_RETURN(std::vector<int> joints, ResolveJoints(skeleton, request.joints(), "joints"));
  ARMATURE_RETURN_IF_ERROR(ValidateStreamWork(1, static_cast<int64_t>(skeleton.size()), pacing.fps, limits, "clip"));
  return ClipStreamPlan(std::move(ref), request.interpolation(), request.space(), std::move(joints));
}

ClipStreamPlan::ClipStreamPlan(PartRef<NamedClip> clip, v1::Interpolation interpolation, v1::Space space,
                               std::vector<int> joints)
    : clip_(std::move(clip)), interpolation_(interpolation), space_(space), joints_(std::move(joints)) {
  ws_.Resize(clip_.part->runtime->skeleton->size());
  context_.Resize(*clip_.part->runtime);
}

double ClipStreamPlan::duration() const { return clip_.part->runtime->duration; }

Status ClipStreamPlan::Fill(uint64_t index, double t, WrapMode wrap, Frame& frame) {
  const CompressedClip& clip = *clip_.part->runtime;
  ARMATURE_RETURN_IF_ERROR(
      (ClipSamplingJob{clip_.part->runtime.get(), t, wrap, &context_, ws_.local, FromProto(interpolation_)}.Run()));
  frame.set_index(index);
  frame.set_time(t);
  if (index == 0) {
    for (int j : joints_) frame.add_joints(j);
    frame.set_skeleton(clip_.part->skeleton_name);
  }
  PackPose(*clip.skeleton, space_, joints_, ws_, frame.mutable_pose());
  return Status::Ok();
}

void ClipStreamPlan::Done(uint64_t frames) const {
  spdlog::debug("stream of '{}' done after {} frames", clip_.part->name, frames);
}

}  // namespace armature::server
