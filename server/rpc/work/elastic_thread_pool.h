// A task queue with a thread per job being run, made on demand up to a
// maximum; jobs beyond it wait. The HTTP server's connections use one
// (cpp-httplib keeps a connection on one worker for its whole keep-alive life
// and an SSE stream for as long as it plays, so a fixed pool of a few threads
// would let a handful of streams or slow clients block every other request),
// and so do long solves that must not hold gRPC's callback threads.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace armature::server {

class ElasticThreadPool final {
 public:
  explicit ElasticThreadPool(size_t max_threads) : max_threads_(max_threads) {}
  ~ElasticThreadPool() { Shutdown(); }

  void Enqueue(std::function<void()> fn);
  // Runs every queued job, then joins the threads.
  void Shutdown();

  size_t threads() const;

 private:
  void Work();

  const size_t max_threads_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::deque<std::function<void()>> jobs_;
  std::vector<std::thread> threads_;
  size_t idle_ = 0;
  bool shutdown_ = false;
};

}  // namespace armature::server
