#include "server/pose/playback_session.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <spdlog/spdlog.h>

namespace armature::server {
namespace {

// A command is due at a frame whose time is within this of its `at` (k/fps
// rounds: 15/30 must meet 0.5).
constexpr double kTimeTolerance = 1e-9;

std::string MessageContext(uint64_t number) { return "message " + std::to_string(number) + ": "; }

}  // namespace

PlaybackSession::~PlaybackSession() {
  spdlog::debug("playback session on '{}' done after {} frames and {} commands",
                setup_.skeleton.part ? setup_.skeleton.part->name : std::string("?"), frames_, commands_);
}

Status PlaybackSession::Start(const CallStop& /*call*/, const Request& first) {
  if (!first.has_start())
    return Status::InvalidArgument(
        "start: required in the first message (skeleton, fps, space, joints, optional play)");
  if (first.at() != 0) return Status::InvalidArgument("at: the start applies at once; give `at` to later commands");
  ARMATURE_ASSIGN_OR_RETURN(setup_, StartPlayback(*catalog_(), limits_, first.start(), playback_, names_));
  return Status::Ok();
}

Status PlaybackSession::ApplyQueued() {
  const double now = static_cast<double>(frames_) / setup_.fps;
  const Status held = HoldQueued(now);
  queued_.clear();
  ARMATURE_RETURN_IF_ERROR(held);
  return ApplyDue(now);
}

Status PlaybackSession::HoldQueued(double now) {
  size_t later = waiting_.size();  // ApplyDue left only commands due after `now`
  for (auto& [number, command] : queued_) {
    const double at = command.at();
    if (!std::isfinite(at)) return Status::InvalidArgument(MessageContext(number) + "at: must be a finite number");
    if (at < 0) return Status::InvalidArgument(MessageContext(number) + "at: " + std::to_string(at) + " is negative");
    if (at > now + kTimeTolerance && ++later > kMaxWaiting)
      return Status::ResourceExhausted(MessageContext(number) + "at: more than " + std::to_string(kMaxWaiting) +
                                       " commands would wait for their time");
    // A past `at` takes effect now: after the held commands due by now, in the order sent.
    waiting_.emplace(std::pair(std::max(at, now), number), std::move(command));
  }
  return Status::Ok();
}

Status PlaybackSession::ApplyDue(double now) {
  const auto due = [&] { return !waiting_.empty() && waiting_.begin()->first.first <= now + kTimeTolerance; };
  if (!due()) return Status::Ok();
  const auto catalog = catalog_();
  while (due()) {
    auto node = waiting_.extract(waiting_.begin());
    const uint64_t number = node.key().second;
    const Request& command = node.mapped();
    Status status = ApplyPlaybackCommand(*catalog, limits_, command, number, *playback_, names_);
    if (status.ok() && command.has_play()) status = ValidatePlaybackWork(setup_, *playback_, limits_, "play");
    if (!status.ok()) return status.WithContext(MessageContext(number));
  }
  return Status::Ok();
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
