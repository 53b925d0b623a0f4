#include "server/host/http/http_server.h"

#include <sys/socket.h>

#include <httplib.h>
#include <spdlog/spdlog.h>

#include "server/rpc/work/elastic_thread_pool.h"

namespace armature::server {
namespace {

// cpp-httplib's worker queue, served by an elastic pool.
class HttpTaskQueue final : public httplib::TaskQueue {
 public:
  explicit HttpTaskQueue(size_t max_threads) : pool_(max_threads) {}
  void enqueue(std::function<void()> fn) override { pool_.Enqueue(std::move(fn)); }
  void shutdown() override { pool_.Shutdown(); }

 private:
  ElasticThreadPool pool_;
};

}  // namespace

HttpServer::HttpServer(size_t max_threads, const std::string& tls_cert_file, const std::string& tls_key_file,
                       const HttpConnectionLimits& connections)
    : http_(MakeGuardedHttpServer(connections, tls_cert_file, tls_key_file)) {
  http_->new_task_queue = [max_threads] { return new HttpTaskQueue(max_threads); };
  // Small writes (SSE frames) go out at once instead of waiting on Nagle and delayed ACKs.
  http_->set_tcp_nodelay(true);
  // SO_REUSEADDR only: cpp-httplib's default SO_REUSEPORT would let a second server share the port.
  http_->set_socket_options([](int sock) {
    const int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });
  // Alive whatever the store says (an unreachable bucket is served around, not restarted for).
  http_->Get("/healthz", [this](const httplib::Request&, httplib::Response& res) {
    res.set_content(store_json_ ? "{\"status\":\"ok\",\"store\":" + store_json_() + "}\n" : "{\"status\":\"ok\"}\n",
                    "application/json");
  });
  http_->Get("/readyz", [this](const httplib::Request&, httplib::Response& res) {
    res.status = ready_ ? 200 : 503;
    res.set_content(ready_ ? "{\"status\":\"ready\"}\n" : "{\"status\":\"loading\"}\n", "application/json");
  });
}

HttpServer::~HttpServer() { Stop(); }

bool HttpServer::ServeDirectory(const std::string& dir) {
  for (const auto& [ext, type] : {std::pair{"js", "text/javascript"},
                                  {"mjs", "text/javascript"},
                                  {"css", "text/css"},
                                  {"html", "text/html"},
                                  {"json", "application/json"},
                                  {"map", "application/json"},
                                  {"svg", "image/svg+xml"},
                                  {"png", "image/png"}})
    http_->set_file_extension_and_mimetype_mapping(ext, type);
  // The API reference (docs/index.html, rendered from /openapi.json) at /docs as well as /docs/.
  http_->Get("/docs", [](const httplib::Request&, httplib::Response& res) { res.set_redirect("/docs/"); });
  // Cross-origin isolated (everything the viewer loads is its own origin's):
  // its timers then tick in 5 µs, not 100 µs, which the session round trips
  // it reports (0.3-1 ms) need.
  return http_->set_mount_point(
      "/", dir, {{"Cross-Origin-Opener-Policy", "same-origin"}, {"Cross-Origin-Embedder-Policy", "require-corp"}});
}

int HttpServer::Start(const std::string& host, int port) {
  if (!http_->is_valid()) return -1;
  const int bound = port == 0 ? http_->bind_to_any_port(host) : (http_->bind_to_port(host, port) ? port : -1);
  if (bound < 0) return -1;
  WidenListenBacklog(*http_);
  thread_ = std::thread([this] { http_->listen_after_bind(); });
  return bound;
}

void HttpServer::Stop() {
  if (thread_.joinable()) {
    http_->stop();
    thread_.join();
  }
}

}  // namespace armature::server
