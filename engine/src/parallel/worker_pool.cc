#include "worker_pool.h"

#include <algorithm>

namespace armature {

WorkerPool& WorkerPool::Shared() {
  static WorkerPool pool(std::max(1u, std::thread::hardware_concurrency()) - 1);
  return pool;
}

WorkerPool::WorkerPool(size_t workers) {
  threads_.reserve(workers);
  for (size_t i = 0; i < workers; ++i) threads_.emplace_back([this] { Work(); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : threads_) t.join();
}

// Takes chunks of the current job until none are left.
void WorkerPool::Drain() {
  for (size_t i = next_.fetch_add(1); i < chunks_; i = next_.fetch_add(1)) thunk_(fn_, i);
}

void WorkerPool::Work() {
  size_t seen = 0;
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      ++active_;
    }
    Drain();
    {
      std::lock_guard lock(mutex_);
      --active_;
    }
    idle_.notify_all();
  }
}

void WorkerPool::RunImpl(size_t chunks, Thunk thunk, void* fn) {
  std::unique_lock run(run_mutex_, std::try_to_lock);
  if (!run.owns_lock() || threads_.empty() || chunks < 2) {
    for (size_t i = 0; i < chunks; ++i) thunk(fn, i);
    return;
  }
  {
    std::unique_lock lock(mutex_);
    // A worker that woke late for the previous job may still be leaving it.
    idle_.wait(lock, [&] { return active_ == 0; });
    thunk_ = thunk;
    fn_ = fn;
    chunks_ = chunks;
    next_.store(0);
    ++generation_;
  }
  wake_.notify_all();
  Drain();
  // Every chunk is claimed; wait for the ones still running on workers.
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [&] { return active_ == 0; });
}

}  // namespace armature
