#include "server/pose/playback_session.h"

#include <string>

#include <spdlog/spdlog.h>

namespace armature::server {

PlaybackSession::~PlaybackSession() {
  spdlog::debug("playback session on '{}' done after {} frames and {} commands",
                setup_.skeleton.part ? setup_.skeleton.part->name : std::string("?"), frames_, commands_);
}

Status PlaybackSession::Start(const CallStop& /*call*/, const Request& first) {
  if (!first.has_start())
    return Status::InvalidArgument(
        "start: required in the first message (skeleton, fps, space, joints, optional play)");
  ARMATURE_ASSIGN_OR_RETURN(setup_, StartPlayback(*catalog_(), limits_, first.start(), playback_, names_));
  return Status::Ok();
}

Status PlaybackSession::ApplyQueued() {
  Status status;
  const auto catalog = queued_.empty() ? nullptr : catalog_();
  for (const auto& [number, command] : queued_) {
    status = ApplyPlaybackCommand(*catalog, limits_, command, number, *playback_, names_);
    if (status.ok() && command.has_play()) status = ValidatePlaybackWork(setup_, *playback_, limits_, "play");
    if (!status.ok()) {
      status = status.WithContext("message " + std::to_string(number) + ": ");
      break;
    }
  }
  queued_.clear();
  return status;
}

StatusOr<bool> PlaybackSession::NextFrame(bool closed, Frame* frame) {
  const double time = static_cast<double>(frames_) / setup_.fps;
  if (setup_.duration > 0 ? time >= setup_.duration - 1e-9 : closed) return false;
  frame->Clear();
  if (Status st = FillPlaybackFrame(setup_, *playback_, names_, frames_, motion_ws_, pose_ws_, *frame); !st.ok())
    return Status(StatusCode::kInternal, st.message());
  playback_->Advance(1.0 / setup_.fps);
  ++frames_;
  return true;
}

}  // namespace armature::server
