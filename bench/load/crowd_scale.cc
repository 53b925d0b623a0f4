#include "crowd_scale.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "armature/v1/crowd.grpc.pb.h"
#include "call_window.h"

namespace armature_load {
namespace {

namespace v1 = armature::v1;

struct Tick {
  Clock::time_point at;
  double wall_time;  // the server's: since the first frame was due
  uint32_t characters, updated, deferred;
  bool late;
  size_t bytes;
};

// One crowd: the start, then its characters one write after another, then
// the frames until its duration.
class CrowdCall final : public grpc::ClientBidiReactor<v1::CrowdCommand, v1::CrowdFrame>, public CallProgress {
 public:
  CrowdCall(const CrowdScaleOptions& o, double seconds, size_t capacity, Done& done) : CallProgress(done), o_(o) {
    command_.mutable_start()->set_fps(o.fps);
    command_.mutable_start()->set_budget_ms(o.budget_ms);
    command_.mutable_start()->set_share_quantum(o.share_quantum);
    command_.mutable_start()->set_duration(seconds);
    context_.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(static_cast<int>(seconds) + 60));
    ticks_.reserve(capacity);  // no allocation per frame while measuring
  }

  void Begin(v1::CrowdService::Stub& stub) {
    stub.async()->CrowdSession(&context_, this);
    StartRead(&frame_);
    StartWrite(&command_);
    StartCall();
  }

  void OnWriteDone(bool ok) override {
    if (!ok) return;
    if (next_ == o_.characters) return StartWritesDone();  // the duration ends the crowd, not the close
    // Mixed offsets, speeds and significances on the clip, as a crowd of walkers would have.
    const int i = next_++;
    v1::CrowdCharacter& c = *command_.mutable_add();
    c.set_id(static_cast<uint32_t>(i));
    c.set_clip(o_.clip);
    c.set_time_offset(std::fmod(0.37 * i, 10.0));
    c.set_speed(0.8 + 0.4 * (i % 7) / 6.0);
    c.set_significance(-static_cast<double>(i % 100));
    StartWrite(&command_);
  }

  void OnReadDone(bool ok) override {
    if (!ok) return;
    if (joints_ == 0 && frame_.new_layouts_size() > 0) joints_ = frame_.new_layouts(0).joints();
    if (frame_.errors_size() > 0 && refused_.empty()) refused_ = frame_.errors(0).error();
    if (ticks_.size() < ticks_.capacity()) {
      const v1::CrowdTickStats& s = frame_.stats();
      ticks_.push_back({Clock::now(), frame_.wall_time(), s.characters(), s.updated(), s.deferred(), s.late(),
                        frame_.ByteSizeLong()});
    }
    Started();
    StartRead(&frame_);
  }

  void OnDone(const grpc::Status& status) override { Ended(status); }

  void Cancel() { context_.TryCancel(); }
  const std::vector<Tick>& ticks() const { return ticks_; }
  uint32_t joints() const { return joints_; }
  std::string error() const {
    if (!refused_.empty()) return refused_;
    return status().ok() || status().error_code() == grpc::StatusCode::CANCELLED ? "" : status().error_message();
  }

 private:
  const CrowdScaleOptions& o_;
  grpc::ClientContext context_;
  v1::CrowdCommand command_;
  v1::CrowdFrame frame_;
  int next_ = 0;
  uint32_t joints_ = 0;
  std::string refused_;
  std::vector<Tick> ticks_;
};

// The window's figures from every crowd's ticks.
void Judge(const std::vector<std::unique_ptr<CrowdCall>>& calls, Clock::time_point from, Clock::time_point to,
           CrowdScaleOutcome& out) {
  std::vector<double> intervals, server_intervals;
  double deferred = 0, updated = 0, characters = 0, bytes = 0, joint_poses = 0;
  for (const auto& call : calls) {
    const auto& t = call->ticks();
    for (size_t k = 0; k < t.size(); ++k) {
      if (t[k].at < from || t[k].at >= to) continue;
      ++out.frames;
      out.late_ticks += t[k].late ? 1 : 0;
      deferred += t[k].deferred;
      updated += t[k].updated;
      characters += t[k].characters;
      bytes += static_cast<double>(t[k].bytes);
      joint_poses += static_cast<double>(t[k].updated) * call->joints();
      if (k == 0 || t[k - 1].at < from) continue;
      intervals.push_back(1000 * Seconds(t[k].at - t[k - 1].at));
      server_intervals.push_back(1000 * (t[k].wall_time - t[k - 1].wall_time));
    }
  }
  const double ticks = static_cast<double>(out.frames) / std::max<size_t>(1, calls.size());
  out.interval_ms = Summarize(intervals);
  out.server_interval_ms = Summarize(server_intervals);
  out.deferred_per_tick = ticks > 0 ? deferred / ticks : 0;
  out.updated_per_tick = ticks > 0 ? updated / ticks : 0;
  out.wire_bytes_per_joint = joint_poses > 0 ? bytes / joint_poses : 0;
  if (out.server_cpu_percent >= 0 && updated > 0) {
    const double cpu_us = 1e4 * out.server_cpu_percent * out.window_seconds;  // % of a core × s → µs
    out.server_cpu_us_per_update = cpu_us / updated;
    out.server_cpu_us_per_character_tick = cpu_us / characters;
  }
}

}  // namespace

CrowdScaleOutcome RunCrowdScale(const std::vector<std::shared_ptr<grpc::Channel>>& channels,
                                const CrowdScaleOptions& o) {
  CrowdScaleOutcome out;
  constexpr double kOpenAllowance = 15, kMargin = 1;
  const double seconds = kOpenAllowance + o.warmup_seconds + o.seconds + kMargin;
  const size_t capacity = static_cast<size_t>(std::ceil(seconds * o.fps * 1.1)) + 16;
  std::vector<std::unique_ptr<v1::CrowdService::Stub>> stubs;
  for (const auto& c : channels) stubs.push_back(v1::CrowdService::NewStub(c));
  Done done;
  done.left = o.sessions;
  std::vector<std::unique_ptr<CrowdCall>> calls;
  for (int i = 0; i < o.sessions; ++i) calls.push_back(std::make_unique<CrowdCall>(o, seconds, capacity, done));
  const CallWindow w = MeasureCalls(
      calls, done, [&](size_t i) { calls[i]->Begin(*stubs[i % stubs.size()]); }, kOpenAllowance, o.warmup_seconds,
      o.seconds, o.server_pid);
  out.open_seconds = w.open_seconds;
  out.window_seconds = w.seconds;
  out.server_cpu_percent = w.server_cpu_percent;
  out.client_cpu_percent = w.client_cpu_percent;
  for (size_t i = 0; i < calls.size(); ++i) {
    if (!calls[i]->ticks().empty()) ++out.sessions_opened;
    const std::string error = w.ended_early[i] && calls[i]->error().empty() ? "ended early" : calls[i]->error();
    if (!error.empty() && out.sessions_failed++ == 0) out.first_error = error;
  }
  out.frames_expected = static_cast<int64_t>(std::llround(out.window_seconds * o.fps)) * o.sessions;
  Judge(calls, w.start, w.end, out);
  return out;
}

}  // namespace armature_load
