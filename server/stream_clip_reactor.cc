#include "server/stream_clip_reactor.h"

#include <cmath>

#include <spdlog/spdlog.h>

#include "armature/engine/clip.h"

namespace armature::server {

StreamClipReactor::StreamClipReactor(FrameScheduler& scheduler, PartRef<NamedClip> clip,
                                     v1::StreamClipRequest request, std::vector<int> joints)
    : clip_(std::move(clip)), request_(std::move(request)), joints_(std::move(joints)), scheduler_(scheduler),
      start_(std::chrono::steady_clock::now()) {
  ws_.Resize(clip_.part->clip->skeleton->size());
  std::lock_guard lock(mu_);
  SendNext();
}

void StreamClipReactor::SendNext() {
  if (cancelled_) return FinishOnce(grpc::Status::CANCELLED);
  const Clip& clip = *clip_.part->clip;
  const double wall = static_cast<double>(index_) / request_.fps();
  if (request_.duration() > 0 && wall >= request_.duration() - 1e-9) return FinishOnce(grpc::Status::OK);
  double t = request_.start_time() + request_.speed() * wall;
  if (!request_.loop() && (t > clip.duration + 1e-9 || t < -1e-9)) {
    // Past an end: the last frame was the end itself, so stop.
    if (index_ > 0) return FinishOnce(grpc::Status::OK);
  }
  t = WrapTime(t, clip.duration, request_.loop() ? WrapMode::kLoop : WrapMode::kClamp);

  SampleOptions options;
  options.interpolation = FromProto(request_.interpolation());
  options.wrap = request_.loop() ? WrapMode::kLoop : WrapMode::kClamp;
  if (Status st = SampleClip(clip, t, options, ws_.local); !st.ok())
    return FinishOnce(grpc::Status(grpc::StatusCode::INTERNAL, st.message()));

  frame_.Clear();
  frame_.set_index(index_);
  frame_.set_time(t);
  frame_.set_wall_time(std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
  if (index_ == 0) {
    for (int j : joints_) frame_.add_joints(j);
    frame_.set_skeleton(clip_.part->skeleton);
  }
  PackPose(*clip.skeleton, request_.space(), joints_, ws_, frame_.mutable_pose());
  ++index_;
  write_pending_ = true;
  StartWrite(&frame_);
}

void StreamClipReactor::OnWriteDone(bool ok) {
  std::lock_guard lock(mu_);
  write_pending_ = false;
  if (!ok) return FinishOnce(grpc::Status(grpc::StatusCode::CANCELLED, "the client went away"));
  if (cancelled_ || finished_) return FinishOnce(grpc::Status::CANCELLED);
  // Frame k is due at start + k/fps; a late frame goes at once.
  const auto due = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                std::chrono::duration<double>(static_cast<double>(index_) / request_.fps()));
  Ref();
  scheduler_.Schedule(due, [this] {
    {
      std::lock_guard lock(mu_);
      if (!finished_) SendNext();
    }
    Unref();
  });
}

void StreamClipReactor::OnCancel() {
  std::lock_guard lock(mu_);
  cancelled_ = true;
  // Waiting for a scheduled frame: finish now rather than at its due time.
  if (!write_pending_) FinishOnce(grpc::Status::CANCELLED);
}

void StreamClipReactor::OnDone() {
  spdlog::debug("stream of '{}' done after {} frames", clip_.part->name, index_);
  Unref();
}

void StreamClipReactor::FinishOnce(grpc::Status status) {
  if (finished_) return;
  finished_ = true;
  Finish(std::move(status));
}

}  // namespace armature::server
