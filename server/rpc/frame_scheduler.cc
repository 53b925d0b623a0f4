#include "server/rpc/frame_scheduler.h"

namespace armature::server {

FrameScheduler::FrameScheduler() : thread_([this] { Run(); }) {}

FrameScheduler::~FrameScheduler() { Stop(); }

void FrameScheduler::Schedule(Clock::time_point due, std::function<void()> task) {
  {
    std::lock_guard lock(mu_);
    if (!stopping_) {
      queue_.push({due, sequence_++, std::move(task)});
      cv_.notify_one();
      return;
    }
  }
  task();  // stopped: run now, so the caller's state machine still completes
}

void FrameScheduler::Stop() {
  {
    std::lock_guard lock(mu_);
    stopping_ = true;
  }
  cv_.notify_one();
  if (thread_.joinable()) thread_.join();
}

void FrameScheduler::Run() {
  std::unique_lock lock(mu_);
  while (true) {
    if (queue_.empty()) {
      if (stopping_) return;
      cv_.wait(lock);
      continue;
    }
    // When stopping, what is left runs at once.
    if (!stopping_ && queue_.top().due > Clock::now()) {
      cv_.wait_until(lock, queue_.top().due);
      continue;
    }
    auto task = std::move(const_cast<Entry&>(queue_.top()).task);
    queue_.pop();
    lock.unlock();
    task();
    lock.lock();
  }
}

}  // namespace armature::server
