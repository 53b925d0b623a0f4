// Internal: a tiny pool of worker threads for splitting one call's work
// across the machine's cores, without allocating per call.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

namespace armature {

class WorkerPool {
 public:
  // The process-wide pool: hardware_concurrency() − 1 workers, started on first use.
  static WorkerPool& Shared();

  explicit WorkerPool(size_t workers);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  size_t workers() const { return threads_.size(); }

  // Calls fn(i) for every i in [0, chunks), on the calling thread and the idle
  // workers, and returns when all are done. When another call is using the
  // pool the caller runs every chunk itself (concurrent requests already keep
  // the cores busy).
  template <class Fn>
  void Run(size_t chunks, Fn&& fn) {
    using F = std::remove_reference_t<Fn>;
    RunImpl(
        chunks, [](void* f, size_t i) { (*static_cast<F*>(f))(i); }, const_cast<void*>(static_cast<const void*>(&fn)));
  }

 private:
  using Thunk = void (*)(void*, size_t);
  void RunImpl(size_t chunks, Thunk thunk, void* fn);
  void Work();
  void Drain();

  std::vector<std::thread> threads_;
  std::mutex run_mutex_;  // one job at a time
  std::mutex mutex_;
  std::condition_variable wake_;  // workers: a new job or stop
  std::condition_variable idle_;  // caller: workers left the job
  size_t generation_ = 0;
  size_t active_ = 0;  // workers inside Drain; a job is only replaced when 0
  bool stop_ = false;
  // The current job, written under mutex_ while no worker is active.
  Thunk thunk_ = nullptr;
  void* fn_ = nullptr;
  size_t chunks_ = 0;
  std::atomic<size_t> next_{0};
};

// Splits [0, n) into chunks_per_thread·(workers + 1) contiguous ranges and
// calls fn(begin, end) for each on `pool`; without a pool, fn(0, n) on the
// calling thread. Several chunks per thread even out uneven ranges.
template <class Fn>
void ParallelRanges(WorkerPool* pool, size_t n, size_t chunks_per_thread, Fn&& fn) {
  if (!pool) {
    fn(size_t{0}, n);
    return;
  }
  const size_t chunks = chunks_per_thread * (pool->workers() + 1);
  pool->Run(chunks, [&](size_t c) { fn(n * c / chunks, n * (c + 1) / chunks); });
}

}  // namespace armature
