// GET /metrics on the HTTP port, in the Prometheus text format.
#pragma once

#include <memory>

#include "server/host/auth/bearer_tokens.h"
#include "server/rpc/metrics.h"

namespace httplib {
class Server;
}

namespace armature::server {

// With `tokens` (--auth-token-file) a scrape needs "Authorization: Bearer
// <token>" like every API call; otherwise 401. Health endpoints stay open.
void ServeMetrics(httplib::Server& http, const Metrics& metrics, std::shared_ptr<const BearerTokens> tokens);

}  // namespace armature::server
