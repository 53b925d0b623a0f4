// Configurable limits; going over one is RESOURCE_EXHAUSTED naming it.
#pragma once

#include <cstddef>
#include <cstdint>

namespace armature::server {

struct Limits {
  int64_t max_upload_bytes = 256ll << 20;     // --max-upload-mb
  int64_t max_message_bytes = 64ll << 20;     // gRPC send/receive
  int64_t max_request_bytes = 4ll << 20;      // --max-request-kb: REST JSON bodies (HTTP 413 above)
  size_t max_http_threads = 256;              // --http-threads: HTTP connections served at once
  double http_head_timeout_seconds = 10;      // --http-head-timeout: TLS handshake, request line and headers
  int max_http_connections_per_address = 64;  // --http-max-connections-per-address
  size_t max_times_per_request = 100000;      // EvaluateClip.times
  double max_stream_fps = 240;
  int max_motion_layers = 32;                // layers of one motion
  int max_motion_mask_joints = 4096;         // mask entries of one motion layer
  int64_t max_clip_frames = 1000000;         // --max-clip-frames: frames of one imported clip
  int64_t max_mesh_vertices = 5000000;       // --max-mesh-vertices: vertices of one imported mesh
  int max_ik_iterations = 1000;              // --max-ik-iterations: solver iterations one IK request may ask for
  int max_ik_effectors = 64;                 // --max-ik-effectors: effectors of one IK request
  int64_t max_ik_work = 5000000;             // --max-ik-work: effectors × chain joints × iterations of one IK request
  int max_sessions_per_client = 16;          // --max-sessions-per-client: open IK/deformation sessions per client
  int max_streams_per_client = 64;           // --max-streams-per-client: open server-streaming/bidi calls per client
  int max_streams = 1024;                    // --max-streams: open server-streaming/bidi calls in all
  int max_sessions = 256;                    // --max-sessions: open IK/deformation sessions in all
  int max_ik_sessions = 64;                  // --max-ik-sessions: IK sessions open at once, all clients
  int64_t deform_cache_bytes = 256ll << 20;  // --deform-cache-mb: unary Deform factorizations kept (0: none)
  // Work budgets, counted in joint samples (one layer of one joint at one time), checked before any work.
  int64_t max_request_work =
      20000000;  // --max-request-work: layers × times × joints of one EvaluateClip/EvaluateMotion
  int64_t max_stream_work = 2000000;  // --max-stream-work: layers × joints × fps of one pose stream or playback session
  // Heavy unary calls run on their own pool so that gRPC's threads stay free for cheap calls and health.
  int heavy_threads = 0;                    // --heavy-threads: heavy calls run at once (0: the cores, at least 2)
  int heavy_queue = 0;                      // --heavy-queue: heavy calls waiting beyond those (0: 4 per thread)
  int64_t max_assets_bytes = 1024ll << 20;  // --max-assets-mb: estimated memory of all loaded assets
  int64_t max_image_bytes = 32ll << 20;     // --max-image-mb: one material image's stored bytes
  // Crowds (CrowdSession): a tick's work budget per session, and characters per session and in all.
  double crowd_budget_ms = 4;               // --crowd-budget-ms: a session's default and largest budget
  int max_crowd_characters = 10000;         // --max-crowd-characters: characters of one crowd session
  int max_crowd_characters_total = 100000;  // --max-crowd-characters-total: characters of every crowd
  double crowd_write_timeout_seconds = 10;  // --crowd-write-timeout-seconds: a crowd that stops reading is dropped
  int max_concurrent_uploads = 4;           // --max-concurrent-uploads: ImportAsset calls (gRPC and REST) at once
};

}  // namespace armature::server
