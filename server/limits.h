// Configurable limits; going over one is RESOURCE_EXHAUSTED naming it.
#pragma once

#include <cstddef>
#include <cstdint>

namespace armature::server {

struct Limits {
  int64_t max_upload_bytes = 256ll << 20;  // --max-upload-mb
  int64_t max_message_bytes = 64ll << 20;  // gRPC send/receive
  int64_t max_request_bytes = 4ll << 20;   // --max-request-kb: REST JSON bodies (HTTP 413 above)
  size_t max_http_threads = 256;           // --http-threads: HTTP connections served at once
  size_t max_times_per_request = 100000;   // EvaluateClip.times
  double max_stream_fps = 240;
  int max_ik_iterations = 10000;  // SolveIkRequest.options.max_iterations
  int max_ik_sessions = 64;       // concurrent IkSession streams
};

}  // namespace armature::server
