#include "stream_scale.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "armature/v1/poses.grpc.pb.h"
#include "call_window.h"

namespace armature_load {
namespace {

namespace v1 = armature::v1;

struct Arrival {
  Clock::time_point at;
  uint64_t index;
  double wall_time;  // the server's: when it wrote the frame, since the stream started
};

class PacedStream final : public grpc::ClientReadReactor<v1::PoseFrame>, public CallProgress {
 public:
  PacedStream(const StreamScaleOptions& o, double stream_seconds, size_t capacity, Done& done) : CallProgress(done) {
    request_.set_clip(o.clip);
    request_.set_fps(o.fps);
    request_.set_loop(true);
    request_.set_duration(stream_seconds);
    request_.set_space(v1::WORLD);
    context_.set_deadline(
        std::chrono::system_clock::now() +
        std::chrono::duration_cast<std::chrono::seconds>(std::chrono::duration<double>(stream_seconds)) +
        std::chrono::seconds(60));
    arrivals_.reserve(capacity);  // no allocation per frame while measuring
  }

  void Begin(v1::PoseService::Stub& stub) {
    stub.async()->StreamClip(&context_, &request_, this);
    StartRead(&frame_);
    StartCall();
  }

  void OnReadDone(bool ok) override {
    if (!ok) return;
    const auto now = Clock::now();
    if (arrivals_.size() < arrivals_.capacity()) arrivals_.push_back({now, frame_.index(), frame_.wall_time()});
    Started();
    StartRead(&frame_);
  }

  void OnDone(const grpc::Status& status) override { Ended(status); }

  void Cancel() { context_.TryCancel(); }
  const std::vector<Arrival>& arrivals() const { return arrivals_; }

 private:
  grpc::ClientContext context_;
  v1::StreamClipRequest request_;
  v1::PoseFrame frame_;
  std::vector<Arrival> arrivals_;
};

}  // namespace

StreamScaleOutcome RunStreamScale(const std::vector<std::shared_ptr<grpc::Channel>>& channels,
                                  const StreamScaleOptions& o) {
  StreamScaleOutcome out;
  // Streams end on their own (the request's duration); opening N of them
  // takes a moment, so each plays long enough to cover opening, warm-up,
  // window and a margin.
  constexpr double kOpenAllowance = 10, kMargin = 1;
  const double stream_seconds = kOpenAllowance + o.warmup_seconds + o.seconds + kMargin;
  const size_t capacity = static_cast<size_t>(std::ceil(stream_seconds * o.fps * 1.1)) + 16;
  std::vector<std::unique_ptr<v1::PoseService::Stub>> stubs;
  for (const auto& c : channels) stubs.push_back(v1::PoseService::NewStub(c));
  Done done;
  done.left = o.streams;
  std::vector<std::unique_ptr<PacedStream>> streams;
  for (int i = 0; i < o.streams; ++i)
    streams.push_back(std::make_unique<PacedStream>(o, stream_seconds, capacity, done));
  const CallWindow w = MeasureCalls(
      streams, done, [&](size_t i) { streams[i]->Begin(*stubs[i % stubs.size()]); }, kOpenAllowance, o.warmup_seconds,
      o.seconds, o.server_pid);
  // One that ended before the window's end failed, whatever its status.
  const auto open_start = w.open_start, window_start = w.start, window_end = w.end;
  const std::vector<bool>& ended_early = w.ended_early;
  out.open_seconds = w.open_seconds;
  out.window_seconds = w.seconds;
  out.server_cpu_percent = w.server_cpu_percent;
  out.client_cpu_percent = w.client_cpu_percent;

  const double period_ms = 1000.0 / o.fps;
  std::vector<double> intervals, deviations, stream_deviations, server_late;
  intervals.reserve(static_cast<size_t>(o.streams * o.seconds * o.fps * 1.2));
  deviations.reserve(intervals.capacity());
  for (size_t i = 0; i < streams.size(); ++i) {
    const PacedStream* s = streams[i].get();
    const auto& a = s->arrivals();
    if (!a.empty()) ++out.streams_opened;
    if (ended_early[i] || (!s->status().ok() && s->status().error_code() != grpc::StatusCode::CANCELLED)) {
      if (out.streams_failed++ == 0)
        out.first_error = s->status().ok() ? "ended before the window's end" : s->status().error_message();
    }
    for (size_t k = 1; k < a.size(); ++k)
      if (a[k].index > a[k - 1].index + 1) out.frames_lost += static_cast<int64_t>(a[k].index - a[k - 1].index - 1);
    if (a.empty()) continue;
    // The stream's schedule: the earliest offset of arrival − index/fps, so
    // lateness is measured against its best-case clock, drift included.
    double anchor = INFINITY;
    for (const Arrival& x : a) anchor = std::min(anchor, Seconds(x.at - open_start) - x.index / o.fps);
    stream_deviations.clear();
    for (size_t k = 0; k < a.size(); ++k) {
      if (a[k].at < window_start || a[k].at >= window_end) continue;
      ++out.frames;
      const double late_ms = 1000 * (Seconds(a[k].at - open_start) - a[k].index / o.fps - anchor);
      out.max_late_ms = std::max(out.max_late_ms, late_ms);
      if (late_ms > o.late_ms) ++out.frames_late;
      // The server's own lateness: when it wrote frame k against k/fps.
      server_late.push_back(std::max(0.0, 1000 * (a[k].wall_time - a[k].index / o.fps)));
      if (k == 0 || a[k - 1].at < window_start) continue;
      const double interval = 1000 * Seconds(a[k].at - a[k - 1].at);
      intervals.push_back(interval);
      deviations.push_back(std::abs(interval - period_ms));
      stream_deviations.push_back(deviations.back());
    }
    out.worst_stream_p99_deviation_ms = std::max(out.worst_stream_p99_deviation_ms, Summarize(stream_deviations).p99);
  }
  out.frames_expected = static_cast<int64_t>(std::llround(out.window_seconds * o.fps)) * o.streams;
  out.interval_ms = Summarize(intervals);
  out.deviation_ms = Summarize(deviations);
  out.server_late_ms = Summarize(server_late);
  return out;
}

}  // namespace armature_load
