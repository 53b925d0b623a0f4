#include "server/host/metrics_http.h"

#include <httplib.h>
#include <nlohmann/json.hpp>

namespace armature::server {

void ServeMetrics(httplib::Server& http, const Metrics& metrics, std::shared_ptr<const BearerTokens> tokens) {
  http.Get("/metrics", [&metrics, tokens](const httplib::Request& req, httplib::Response& res) {
    if (tokens) {
      const Status st = tokens->Check(req.get_header_value("Authorization"));
      if (!st.ok()) {
        res.status = 401;
        res.set_header("WWW-Authenticate", "Bearer");
        res.set_content(nlohmann::json{{"code", "UNAUTHENTICATED"}, {"message", st.message()}}.dump() + "\n",
                        "application/json");
        return;
      }
    }
    res.set_content(metrics.Render(), "text/plain; version=0.0.4; charset=utf-8");
  });
}

}  // namespace armature::server
