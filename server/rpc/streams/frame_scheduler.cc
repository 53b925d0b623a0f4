#include "server/rpc/streams/frame_scheduler.h"

namespace armature::server {

FrameScheduler::FrameScheduler() : thread_([this] { Run(); }) {}

FrameScheduler::~FrameScheduler() { Stop(); }

void FrameScheduler::Schedule(Clock::time_point due, std::function<void()> task) {
  {
    std::lock_guard lock(mu_);
    if (!stopping_) {
      // The thread sleeps until the earliest due time: only a new earliest
      // task changes when it must wake.
      const bool earliest = queue_.empty() || due < queue_.top().due;
      queue_.push({due, sequence_++, std::move(task)});
      if (earliest) cv_.notify_one();
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

FrameScheduler::Counts FrameScheduler::counts() const {
  std::lock_guard lock(mu_);
  return counts_;
}

void FrameScheduler::Run() {
  std::vector<std::function<void()>> batch;  // reused: no allocation per wake-up once grown
  std::unique_lock lock(mu_);
  while (true) {
    if (queue_.empty()) {
      if (stopping_) return;
      cv_.wait(lock);
      continue;
    }
    // When stopping, what is left runs at once.
    const auto now = Clock::now();
    if (!stopping_ && queue_.top().due > now) {
      cv_.wait_until(lock, queue_.top().due);
      continue;
    }
    // Everything due by now, in due order, outside the lock (a task may
    // Schedule the next one).
    while (!queue_.empty() && (stopping_ || queue_.top().due <= now)) {
      batch.push_back(std::move(const_cast<Entry&>(queue_.top()).task));
      queue_.pop();
    }
    ++counts_.wakeups;
    counts_.tasks += batch.size();
    lock.unlock();
    for (auto& task : batch) task();
    batch.clear();
    lock.lock();
  }
}

}  // namespace armature::server
