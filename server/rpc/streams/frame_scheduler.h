// Runs tasks at given times on one shared thread: how pose streams are paced
// without a sleeping thread per stream. Tasks must be short.
//
// At scale (1,000 streams at 60 fps: 60,000 tasks a second) the thread must
// not wake per task: Schedule wakes it only when the new task is due before
// everything queued, and each wake-up runs every task then due as one batch.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <queue>
#include <thread>
#include <vector>

namespace armature::server {

class FrameScheduler {
 public:
  using Clock = std::chrono::steady_clock;

  FrameScheduler();
  ~FrameScheduler();  // Stop()

  void Schedule(Clock::time_point due, std::function<void()> task);
  // Runs every pending task now (so waiting streams can finish) and stops the
  // thread; later tasks run inline.
  void Stop();

  // How often the thread has woken up to run tasks, and how many it ran: at
  // scale the ratio shows the batching.
  struct Counts {
    uint64_t wakeups = 0;
    uint64_t tasks = 0;
  };
  Counts counts() const;

 private:
  struct Entry {
    Clock::time_point due;
    uint64_t sequence;
    std::function<void()> task;
    bool operator>(const Entry& o) const { return due != o.due ? due > o.due : sequence > o.sequence; }
  };
  void Run();

  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue_;
  uint64_t sequence_ = 0;
  bool stopping_ = false;
  Counts counts_;
  std::thread thread_;
};

}  // namespace armature::server
