#include "server/pose/stream_motion_reactor.h"

namespace armature::server {

StreamMotionReactor::StreamMotionReactor(FrameScheduler& scheduler, StreamPacing pacing, MotionPlan plan,
                                         std::string skeleton, v1::Space space, std::vector<int> joints)
    : PacedStreamReactor(scheduler, pacing, MotionLength(plan)), pacing_(pacing),
      motion_(std::move(plan)), skeleton_(std::move(skeleton)), space_(space), joints_(std::move(joints)) {
  ws_.Resize(motion_.skeleton().size());
  Start();
}

Status StreamMotionReactor::Fill(uint64_t index, double, WrapMode, v1::PoseFrame& frame) {
  // The base's time is wrapped to the motion's length; a motion's is not.
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
