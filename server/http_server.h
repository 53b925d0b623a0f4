// The HTTP side of armature-server: health endpoints now; the REST gateway
// and the viewer register their routes on the same httplib::Server.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

namespace httplib {
class Server;
}

namespace armature::server {

class HttpServer {
 public:
  // `max_threads`: connections served at once (see ElasticThreadPool).
  explicit HttpServer(size_t max_threads = 256);
  ~HttpServer();

  httplib::Server& routes() { return *http_; }
  // Serves the files under `dir` at "/" (index.html for directories).
  bool ServeDirectory(const std::string& dir);
  // Binds and starts serving on a thread; returns the bound port or -1.
  int Start(const std::string& host, int port);
  void Stop();
  void SetReady(bool ready) { ready_ = ready; }

 private:
  std::unique_ptr<httplib::Server> http_;
  std::thread thread_;
  std::atomic<bool> ready_{false};
};

}  // namespace armature::server
