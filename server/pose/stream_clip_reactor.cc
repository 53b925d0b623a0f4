#include "server/pose/stream_clip_reactor.h"

#include <spdlog/spdlog.h>

#include "server/assets/compiled_clips.h"

namespace armature::server {

StreamClipReactor::StreamClipReactor(FrameScheduler& scheduler, StreamPacing pacing, PartRef<NamedClip> clip,
                                     v1::StreamClipRequest request, std::vector<int> joints)
    : PacedStreamReactor(scheduler, pacing, clip.part->clip->duration), clip_(std::move(clip)),
      request_(std::move(request)), joints_(std::move(joints)) {
  ws_.Resize(clip_.part->clip->skeleton->size());
  Start();
}

Status StreamClipReactor::Fill(uint64_t index, double t, WrapMode wrap, v1::PoseFrame& frame) {
  const Clip& clip = *clip_.part->clip;
  SampleOptions options;
  options.interpolation = FromProto(request_.interpolation());
  options.wrap = wrap;
  ARMATURE_RETURN_IF_ERROR(SampleNamedClip(*clip_.part, t, options, ws_.local));
  frame.set_index(index);
  frame.set_time(t);
  if (index == 0) {
    for (int j : joints_) frame.add_joints(j);
    frame.set_skeleton(clip_.part->skeleton);
  }
  PackPose(*clip.skeleton, request_.space(), joints_, ws_, frame.mutable_pose());
  return Status::Ok();
}

void StreamClipReactor::OnStreamDone(uint64_t frames) {
  spdlog::debug("stream of '{}' done after {} frames", clip_.part->name, frames);
}

}  // namespace armature::server
