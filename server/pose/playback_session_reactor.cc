#include "server/pose/playback_session_reactor.h"

#include <spdlog/spdlog.h>

#include "server/rpc/call_guard.h"
#include "server/rpc/grpc_status.h"

namespace armature::server {

PlaybackSessionReactor::PlaybackSessionReactor(grpc::CallbackServerContext* context, AssetStore& store,
                                               const Limits& limits, FrameScheduler& scheduler,
                                               SessionAdmission& sessions, StreamAdmission::Ticket stream)
    : context_(context), store_(store), limits_(limits), scheduler_(scheduler), stream_(std::move(stream)) {
  std::lock_guard lock(mu_);
  auto ticket = sessions.Admit(*context, SessionKind::kPlayback);
  if (!ticket.ok()) {
    End(ToGrpcStatus(ticket.status()));
    return;
  }
  ticket_ = std::move(*ticket);
  ReadNext();
}

void PlaybackSessionReactor::Guarded(const std::function<void()>& fn) {
  GuardCallback(
      context_, "PlaybackSession",
      [&] {
        std::lock_guard lock(mu_);
        fn();
      },
      [this](grpc::Status st) {
        std::lock_guard lock(mu_);
        End(std::move(st));
      });
}

void PlaybackSessionReactor::OnReadDone(bool ok) {
  Guarded([&] { ReadDone(ok); });
}

void PlaybackSessionReactor::OnWriteDone(bool ok) {
  Guarded([&] { WriteDone(ok); });
}

void PlaybackSessionReactor::OnCancel() {
  std::lock_guard lock(mu_);
  cancelled_ = true;
  End(grpc::Status::CANCELLED);
}

void PlaybackSessionReactor::OnDone() {
  spdlog::debug("playback session on '{}' done after {} frames and {} commands",
                setup_.skeleton.part ? setup_.skeleton.part->name : std::string("?"), index_, messages_);
  ticket_.Release();
  stream_.Release();
  Unref();
}

void PlaybackSessionReactor::Unref() {
  if (refs_.fetch_sub(1, std::memory_order_acq_rel) == 1) delete this;
}

void PlaybackSessionReactor::ReadNext() {
  if (finished_ || reading_ || read_closed_) return;
  reading_ = true;
  StartRead(&request_);
}

void PlaybackSessionReactor::ReadDone(bool ok) {
  reading_ = false;
  if (finished_) return;
  if (!ok) {  // the client closed its side (or went away)
    read_closed_ = true;
    if (!started_) End(grpc::Status::OK);
    return;  // with a duration the session plays on; without, the next frame ends it
  }
  if (!started_) {
    if (!request_.has_start())
      return End(ToGrpcStatus(Status::InvalidArgument(
          "start: required in the first message (skeleton, fps, space, joints, optional play)")));
    auto setup = StartPlayback(*store_.Snapshot(), limits_, request_.start(), playback_, names_);
    if (!setup.ok()) return End(ToGrpcStatus(setup.status()));
    setup_ = std::move(*setup);
    started_ = true;
    start_ = std::chrono::steady_clock::now();
    request_.Clear();
    if (!FillNext()) return;
    Write();
    return ReadNext();
  }
  queued_.emplace_back(++messages_, std::move(request_));
  request_.Clear();
  if (queued_.size() < kMaxQueuedCommands) ReadNext();
}

void PlaybackSessionReactor::WriteDone(bool ok) {
  write_pending_ = false;
  if (end_requested_) return End(end_status_);
  if (!ok) return End(grpc::Status(grpc::StatusCode::CANCELLED, "the client went away"));
  if (finished_) return;
  if (cancelled_) return End(grpc::Status::CANCELLED);
  // Frame k is due at start + k/fps; a late frame goes at once.
  const auto due = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                std::chrono::duration<double>(static_cast<double>(index_) / setup_.fps));
  if (!FillNext()) return;
  refs_.fetch_add(1, std::memory_order_relaxed);
  scheduler_.Schedule(due, [this] {
    {
      std::lock_guard lock(mu_);
      if (cancelled_) End(grpc::Status::CANCELLED);
      if (!finished_) Write();
    }
    Unref();
  });
}

bool PlaybackSessionReactor::FillNext() {
  if (cancelled_) return End(grpc::Status::CANCELLED), false;
  Status st;
  try {  // the exception boundary of this callback's frame (call_guard.h)
    const auto catalog = queued_.empty() ? nullptr : store_.Snapshot();
    for (const auto& [number, command] : queued_) {
      st = ApplyPlaybackCommand(*catalog, limits_, command, number, *playback_, names_);
      if (st.ok() && command.has_play()) st = ValidatePlaybackWork(setup_, *playback_, limits_, "play");
      if (!st.ok()) {
        st = st.WithContext("message " + std::to_string(number) + ": ");
        break;
      }
    }
    queued_.clear();
    if (st.ok()) {
      ReadNext();  // reading paused on a full queue resumes
      const double time = static_cast<double>(index_) / setup_.fps;
      if (setup_.duration > 0 ? time >= setup_.duration - 1e-9 : read_closed_) return End(grpc::Status::OK), false;
      frame_.Clear();
      st = FillPlaybackFrame(setup_, *playback_, names_, index_, motion_ws_, pose_ws_, frame_);
      if (!st.ok()) st = Status(StatusCode::kInternal, st.message());
    }
  } catch (...) {
    st = StatusOfCurrentException(context_, "playback frame");
  }
  if (!st.ok()) return End(ToGrpcStatus(st)), false;
  playback_->Advance(1.0 / setup_.fps);
  ++index_;
  return true;
}

void PlaybackSessionReactor::Write() {
  frame_.set_wall_time(std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
  write_pending_ = true;
  StartWrite(&frame_);
}

void PlaybackSessionReactor::End(grpc::Status status) {
  if (finished_) return;
  if (write_pending_) {  // finish when the write in flight is done
    if (!end_requested_) end_status_ = std::move(status);
    end_requested_ = true;
    return;
  }
  finished_ = true;
  // Free the place before the client hears the session is over, so it can
  // open another at once.
  ticket_.Release();
  Finish(std::move(status));
}

}  // namespace armature::server
