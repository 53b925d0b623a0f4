// Runs tasks at given times on one shared thread: how pose streams are paced
// without a sleeping thread per stream. Tasks must be short.
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

 private:
  struct Entry {
    Clock::time_point due;
    uint64_t sequence;
    std::function<void()> task;
    bool operator>(const Entry& o) const { return due != o.due ? due > o.due : sequence > o.sequence; }
  };
  void Run();

  std::mutex mu_;
  std::condition_variable cv_;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue_;
  uint64_t sequence_ = 0;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace armature::server
