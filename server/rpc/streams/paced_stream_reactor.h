// A server stream that plays a plan in real time: frame k is due at
// start + k/fps and shows clip time start_time + speed·k/fps. The
// FrameScheduler paces it, so no thread sleeps waiting for a frame. What a
// frame carries (a pose, a skinned mesh) is the plan's, which knows no gRPC:
//   using Frame;                 // a message with set_wall_time (set here)
//   double duration() const;     // the played clip's: times wrap or clamp to it
//   Status Fill(uint64_t index, double time, WrapMode wrap, Frame& frame);
//   void Done(uint64_t frames);  // optional: the stream is over
// Fill gets `frame` cleared and `time` already wrapped or clamped; an error
// ends the stream as INTERNAL. It runs on the gRPC thread that saw the last
// write done, so the scheduler's one thread only starts writes and a large
// mesh never delays other streams.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>

#include <grpcpp/grpcpp.h>

#include "armature/engine/anim/clip.h"
#include "armature/base/status.h"
#include "server/rpc/call_guard.h"
#include "server/rpc/streams/frame_scheduler.h"
#include "server/rpc/grpc_status.h"
#include "server/rpc/streams/stream_admission.h"
#include "server/rpc/stream_pacing.h"

namespace armature::server {

template <class Plan>
class PacedStreamReactor final : public grpc::ServerWriteReactor<typename Plan::Frame> {
  using Frame = typename Plan::Frame;

 public:
  // `pacing` must be validated (ValidatePacing); `stream` keeps the stream's
  // place (--max-streams-per-client) until gRPC is done with the call. Sends
  // the first frame.
  PacedStreamReactor(FrameScheduler& scheduler, StreamPacing pacing, Plan plan, StreamAdmission::Ticket stream)
      : scheduler_(scheduler),
        pacing_(pacing),
        plan_(std::move(plan)),
        clip_duration_(plan_.duration()),
        start_(std::chrono::steady_clock::now()),
        stream_ticket_(std::move(stream)) {
    std::lock_guard lock(mu_);
    if (FillNext()) Write();
  }

  void OnWriteDone(bool ok) override {
    std::lock_guard lock(mu_);
    write_pending_ = false;
    if (!ok) return FinishOnce(grpc::Status(grpc::StatusCode::CANCELLED, "the client went away"));
    if (cancelled_ || finished_) return FinishOnce(grpc::Status::CANCELLED);
    // Frame k is due at start + k/fps; a late frame goes at once.
    const auto due = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                  std::chrono::duration<double>(static_cast<double>(index_) / pacing_.fps));
    if (!FillNext()) return;
    refs_.fetch_add(1, std::memory_order_relaxed);
    scheduler_.Schedule(due, [this] {
      {
        std::lock_guard lock(mu_);
        if (cancelled_) FinishOnce(grpc::Status::CANCELLED);
        if (!finished_) Write();
      }
      Unref();
    });
  }

  void OnCancel() override {
    std::lock_guard lock(mu_);
    cancelled_ = true;
    // Waiting for a scheduled frame (filled, not yet written): finish now
    // rather than at its due time.
    if (!write_pending_) FinishOnce(grpc::Status::CANCELLED);
  }

  void OnDone() override {
    stream_ticket_.Release();
    if constexpr (requires { plan_.Done(index_); }) plan_.Done(index_);
    Unref();
  }

 private:
  // Deleted when gRPC is done with it (OnDone) and no scheduled frame is
  // pending: either may come last, on any thread.
  void Unref() {
    if (refs_.fetch_sub(1, std::memory_order_acq_rel) == 1) delete this;
  }

  // Fills frame_ with the next frame; false when the stream has ended
  // instead (cancelled, played out, or a failed Fill). Called with mu_ held.
  bool FillNext() {
    if (cancelled_) return FinishOnce(grpc::Status::CANCELLED), false;
    const double wall = static_cast<double>(index_) / pacing_.fps;
    if (pacing_.duration > 0 && wall >= pacing_.duration - 1e-9) return FinishOnce(grpc::Status::OK), false;
    double t = pacing_.start_time + pacing_.speed * wall;
    // Past an end: the last frame was the end itself, so stop.
    if (!pacing_.loop && (t > clip_duration_ + 1e-9 || t < -1e-9) && index_ > 0)
      return FinishOnce(grpc::Status::OK), false;
    const WrapMode wrap = pacing_.loop ? WrapMode::kLoop : WrapMode::kClamp;
    t = WrapTime(t, clip_duration_, wrap);
    Status st;
    try {  // the exception boundary of this gRPC callback (call_guard.h)
      frame_.Clear();
      st = plan_.Fill(index_, t, wrap, frame_);
      if (!st.ok()) st = Status(StatusCode::kInternal, st.message());
    } catch (...) {
      st = StatusOfCurrentException(nullptr, "stream frame");
    }
    if (!st.ok()) return FinishOnce(ToGrpcStatus(st)), false;
    ++index_;
    return true;
  }

  void Write() {  // called with mu_ held, frame_ filled
    frame_.set_wall_time(std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
    write_pending_ = true;
    this->StartWrite(&frame_);
  }

  void FinishOnce(grpc::Status status) {  // called with mu_ held
    if (finished_) return;
    finished_ = true;
    this->Finish(std::move(status));
  }

  FrameScheduler& scheduler_;
  const StreamPacing pacing_;
  Plan plan_;
  const double clip_duration_;
  const std::chrono::steady_clock::time_point start_;
  Frame frame_;
  uint64_t index_ = 0;
  StreamAdmission::Ticket stream_ticket_;

  std::atomic<int> refs_{1};  // OnDone's
  std::mutex mu_;
  bool cancelled_ = false;
  bool finished_ = false;
  bool write_pending_ = false;
};

// A stream that fails before its first frame.
template <class Frame>
class FailedStream final : public grpc::ServerWriteReactor<Frame> {
 public:
  explicit FailedStream(const Status& status) { this->Finish(ToGrpcStatus(status)); }
  void OnDone() override { delete this; }
};

}  // namespace armature::server
