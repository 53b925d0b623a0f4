// The HTTP side of armature-server: health endpoints, metrics, the REST
// gateway and the viewer all register their routes on one httplib::Server.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "server/host/http/http_connection.h"

namespace httplib {
class Server;
}

namespace armature::server {

class HttpServer {
 public:
  // `max_threads`: connections served at once (see ElasticThreadPool);
  // `connections`: each one's head deadline and the cap per address. With
  // a PEM certificate chain and key (--tls-cert, --tls-key) it serves HTTPS.
  explicit HttpServer(size_t max_threads = 256, const std::string& tls_cert_file = "",
                      const std::string& tls_key_file = "", const HttpConnectionLimits& connections = {});
  ~HttpServer();

  httplib::Server& routes() { return *http_; }
  // Serves the files under `dir` at "/" (index.html for directories).
  bool ServeDirectory(const std::string& dir);
  // Binds and starts serving on a thread; returns the bound port or -1
  // (also when the TLS certificate or key could not be loaded).
  int Start(const std::string& host, int port);
  void Stop();
  void SetReady(bool ready) { ready_ = ready; }
  // /healthz's "store" member: a JSON object, asked at each check. Call before Start.
  void SetStoreHealth(std::function<std::string()> store_json) { store_json_ = std::move(store_json); }

 private:
  std::unique_ptr<httplib::Server> http_;
  std::thread thread_;
  std::function<std::string()> store_json_;
  std::atomic<bool> ready_{false};
};

}  // namespace armature::server
