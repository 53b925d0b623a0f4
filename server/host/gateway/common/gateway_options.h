// What the gateway is configured with (armature_server.cc fills it from the
// flags): body and answer limits, deadlines, stream slots, WebSocket timeouts,
// CORS origins, the tokens and the trusted proxies.
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "server/host/auth/bearer_tokens.h"
#include "server/host/gateway/common/forwarded_for.h"

namespace armature::server::gateway {

struct GatewayOptions {
  std::vector<std::string> cors_origins;  // --cors-origin
  size_t max_request_bytes = 4u << 20;    // JSON, protobuf and gRPC-Web bodies (--max-request-kb)
  size_t max_upload_bytes = 256u << 20;   // raw bytes bodies, i.e. imports (--max-upload-mb)
  size_t upload_chunk_bytes = 1u << 20;   // raw bodies reach client-streaming RPCs in chunks of this size
  size_t max_reply_bytes = 64u << 20;     // a JSON answer's text (--max-message-mb)
  // Deadline of calls that do not stream responses, unless the request sends
  // `grpc-timeout`. Response streams have none: they end with the client.
  std::chrono::milliseconds default_timeout{30000};
  // A response stream whose first response comes this fast answers errors
  // with a plain HTTP error; later ones arrive as the final SSE status event.
  std::chrono::milliseconds first_response_wait{2000};
  std::chrono::milliseconds sse_heartbeat{15000};
  size_t max_streams =
      200;  // open SSE and gRPC-Web streams and WebSocket sessions; more are refused (each holds an HTTP thread)
  // A WebSocket session whose client sends no message for this long is closed (1001).
  std::chrono::milliseconds websocket_idle_timeout{300000};
  // Longest a write to a WebSocket client may block (a client that stops reading).
  std::chrono::milliseconds websocket_write_timeout{10000};
  // --auth-token-file: checked before a request body is read, so token-less
  // uploads cost no memory (the gRPC auth gate checks again).
  std::shared_ptr<const BearerTokens> tokens;
  // --trust-forwarded-for: proxies whose X-Forwarded-For names the client.
  TrustedProxies trusted_proxies;
};

}  // namespace armature::server::gateway
