#include "server/host/gateway/cors.h"

#include <algorithm>

#include <httplib.h>

#include "server/host/gateway/common/error_mapping.h"

namespace armature::server::gateway {
namespace {
// Request headers a browser page may send to the gateway (gRPC-Web clients
// add x-grpc-web and x-user-agent), and response headers it may read.
constexpr char kAllowedHeaders[] = "authorization, content-type, grpc-timeout, x-request-id, x-grpc-web, x-user-agent";
constexpr char kExposedHeaders[] = "x-request-id, grpc-status, grpc-message";
}  // namespace

CorsPolicy::CorsPolicy(std::vector<std::string> origins) : origins_(std::move(origins)) {
  for (auto& o : origins_) {
    while (!o.empty() && o.back() == '/') o.pop_back();  // "http://a.example/" names the origin http://a.example
    if (o == "*") any_ = true;
  }
}

bool CorsPolicy::Allows(const std::string& origin) const {
  if (origin.empty()) return false;
  return any_ || std::find(origins_.begin(), origins_.end(), origin) != origins_.end();
}

void CorsPolicy::Decorate(const httplib::Request& req, httplib::Response& res) const {
  const std::string origin = req.get_header_value("Origin");
  if (origins_.empty()) return;
  res.set_header("Vary", "Origin");
  if (!Allows(origin)) return;
  res.set_header("Access-Control-Allow-Origin", origin);
  res.set_header("Access-Control-Expose-Headers", kExposedHeaders);
}

void CorsPolicy::AnswerOptions(const httplib::Request& req, httplib::Response& res,
                               const std::string& allowed_methods) const {
  const std::string origin = req.get_header_value("Origin");
  res.set_header("Allow", allowed_methods);
  if (origin.empty() || !req.has_header("Access-Control-Request-Method")) {
    res.status = 204;  // not a preflight
    return;
  }
  if (!Allows(origin)) {
    WriteError(res, 403, grpc::StatusCode::PERMISSION_DENIED,
               "origin '" + origin + "' is not allowed (see --cors-origin)");
    return;
  }
  res.status = 204;
  // Decorate() has already added Access-Control-Allow-Origin and Vary.
  res.set_header("Access-Control-Allow-Methods", allowed_methods);
  res.set_header("Access-Control-Allow-Headers", kAllowedHeaders);
  res.set_header("Access-Control-Max-Age", "600");
}

}  // namespace armature::server::gateway
