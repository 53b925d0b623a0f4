#include "server/pose/motion_stream_plan.h"

#include "server/assets/motion_convert.h"
#include "server/rpc/request_validation.h"
#include "server/rpc/work/work_budget.h"

namespace armature::server {

StatusOr<MotionStreamPlan> MotionStreamPlan::Make(const Catalog& catalog, const Limits& limits,
                                                  const v1::StreamClipRequest& request, const StreamPacing& pacing) {
  ARMATURE_ASSIGN_OR_RETURN(MotionPlan plan, BindMotionProto(catalog, request.motion(), limits, "motion"));
  ARMATURE_ASSIGN_OR_RETURN(std::vector<int> joints, ResolveJoints(*plan.skeleton, request.joints(), "joints"));
  ARMATURE_RETURN_IF_ERROR(ValidateStreamWork(static_cast<int64_t>(plan.layers.size()),
                                              static_cast<int64_t>(plan.skeleton->size()), pacing.fps, limits,
                                              "motion"));
  const v1::Space space = request.space() == v1::WORLD ? v1::WORLD : v1::LOCAL;
  std::string skeleton = catalog.FindClip(request.motion().layers(0).clip())->part->skeleton_name;
  return MotionStreamPlan(pacing, std::move(plan), std::move(skeleton), space, std::move(joints));
}

MotionStreamPlan::MotionStreamPlan(StreamPacing pacing, MotionPlan plan, std::string skeleton, v1::Space space,
                                   std::vector<int> joints)
    : pacing_(pacing),
      motion_(std::move(plan)),
      skeleton_(std::move(skeleton)),
      space_(space),
      joints_(std::move(joints)) {
  ws_.Resize(motion_.skeleton().size());
}

Status MotionStreamPlan::Fill(uint64_t index, double, WrapMode, Frame& frame) {
  // The reactor's time is wrapped to the motion's length; a motion's is not.
  const double t = MotionStreamTime(pacing_, index);
  ARMATURE_RETURN_IF_ERROR(motion_.Next(t, ws_.local, motion_.extracts_root() ? frame.mutable_root_delta() : nullptr));
  frame.set_index(index);
  frame.set_time(t);
  if (index == 0) {
    for (int j : joints_) frame.add_joints(j);
    frame.set_skeleton(skeleton_);
  }
  PackPose(motion_.skeleton(), space_, joints_, ws_, frame.mutable_pose());
  return Status::Ok();
}

}  // namespace armature::server
