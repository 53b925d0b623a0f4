#include "server/host/observability/metrics_http.h"

#include <httplib.h>

#include "server/host/gateway/common/error_mapping.h"

namespace armature::server {

void ServeMetrics(httplib::Server& http, const Metrics& metrics, std::shared_ptr<const BearerTokens> tokens) {
  http.Get("/metrics", [&metrics, tokens](const httplib::Request& req, httplib::Response& res) {
    if (tokens) {
      const Status st = tokens->Check(req.get_header_value("Authorization"));
      if (!st.ok()) {
        // The same body as every other error: {"code": 16, "message": …}.
        gateway::WriteError(res, 401, grpc::StatusCode::UNAUTHENTICATED, st.message());
        res.set_header("WWW-Authenticate", "Bearer");
        return;
      }
    }
    res.set_content(metrics.Render(), "text/plain; version=0.0.4; charset=utf-8");
  });
}

}  // namespace armature::server
