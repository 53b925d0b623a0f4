// The measuring frame of the stream and crowd scale runs: every call begun,
// each one's first frame waited for, a warm-up, then a measured window with
// the server's and this process's CPU, then every call cancelled and waited
// for. A Call is a CallProgress with a Cancel().
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include <grpcpp/grpcpp.h>

#include "proc_cpu.h"

namespace armature_load {

using Clock = std::chrono::steady_clock;

inline double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// Ends when every call is done.
struct Done {
  std::mutex mu;
  std::condition_variable cv;
  int left = 0;
  void One() {
    std::lock_guard lock(mu);
    if (--left == 0) cv.notify_all();
  }
};

// A call's progress as MeasureCalls reads it (any thread); the call reports
// its first frame (Started) and its end (Ended, from OnDone).
class CallProgress {
 public:
  explicit CallProgress(Done& done) : done_(done) {}
  bool started() const { return started_.load(std::memory_order_acquire); }
  bool ended() const { return ended_.load(std::memory_order_acquire); }
  const grpc::Status& status() const { return status_; }  // once ended

 protected:
  void Started() { started_.store(true, std::memory_order_release); }
  void Ended(const grpc::Status& status) {
    status_ = status;
    ended_.store(true, std::memory_order_release);
    done_.One();
  }

 private:
  Done& done_;
  std::atomic<bool> started_{false}, ended_{false};
  grpc::Status status_;
};

struct CallWindow {
  Clock::time_point open_start, start, end;
  double open_seconds = 0;         // from the first call to the last one's first frame
  double seconds = 0;              // the measured window
  double server_cpu_percent = -1;  // of one core, over the window
  double client_cpu_percent = -1;
  std::vector<bool> ended_early;  // per call: over before the window's end (a failure)
};

// `begin(i)` starts call i; calls that have not started after `open_allowance`
// seconds are measured as they are.
template <class Call, class Begin>
CallWindow MeasureCalls(std::vector<std::unique_ptr<Call>>& calls, Done& done, Begin begin, double open_allowance,
                        double warmup, double seconds, int server_pid) {
  CallWindow w;
  w.open_start = Clock::now();
  for (size_t i = 0; i < calls.size(); ++i) begin(i);
  const auto open_limit =
      w.open_start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(open_allowance));
  while (Clock::now() < open_limit) {
    size_t ready = 0;  // playing, or ended (a failure is the caller's to report)
    for (auto& c : calls) ready += c->started() || c->ended() ? 1 : 0;
    if (ready == calls.size()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  w.open_seconds = Seconds(Clock::now() - w.open_start);
  std::this_thread::sleep_for(std::chrono::duration<double>(warmup));
  w.start = Clock::now();
  const double server0 = server_pid > 0 ? ProcessCpuSeconds(server_pid) : -1, client0 = ProcessCpuSeconds(0);
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  w.end = Clock::now();
  const double server1 = server_pid > 0 ? ProcessCpuSeconds(server_pid) : -1, client1 = ProcessCpuSeconds(0);
  w.seconds = Seconds(w.end - w.start);
  if (server0 >= 0 && server1 >= 0) w.server_cpu_percent = 100 * (server1 - server0) / w.seconds;
  if (client0 >= 0 && client1 >= 0) w.client_cpu_percent = 100 * (client1 - client0) / w.seconds;
  // Measured: the rest of each call is not needed.
  for (auto& c : calls) w.ended_early.push_back(c->ended());
  for (auto& c : calls) c->Cancel();
  std::unique_lock lock(done.mu);
  done.cv.wait(lock, [&] { return done.left == 0; });
  return w;
}

}  // namespace armature_load
