#include "server/host/config.h"

#include <filesystem>
#include <utility>
#include <memory>

#include <CLI/CLI.hpp>

#include "armature/build_info.h"
#include "server/host/gateway/common/forwarded_for.h"

namespace armature::server {
namespace {

// Work bounded before it starts, and heavy calls kept off gRPC's threads.
void AddWorkBudgetFlags(CLI::App& app, Limits& limits) {
  app.add_option("--max-request-work", limits.max_request_work,
                 "Most work one EvaluateClip/EvaluateMotion may ask for: layers x times x skeleton joints")
      ->envname("ARMATURE_MAX_REQUEST_WORK")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-stream-work", limits.max_stream_work,
                 "Most work a second one pose stream or playback session may ask for: layers x joints x fps "
                 "(a session's layers: those of every motion playing)")
      ->envname("ARMATURE_MAX_STREAM_WORK")
      ->check(CLI::PositiveNumber);
  app.add_option("--heavy-threads", limits.heavy_threads,
                 "Heavy unary calls (long evaluations) run at once, off gRPC's threads (0: the cores, at least 2)")
      ->envname("ARMATURE_HEAVY_THREADS")
      ->check(CLI::Range(0, 1024));
  app.add_option("--heavy-queue", limits.heavy_queue,
                 "Heavy calls that may wait beyond those running before more are refused (0: 4 per thread)")
      ->envname("ARMATURE_HEAVY_QUEUE")
      ->check(CLI::Range(0, 100000));
}

}  // namespace

namespace {

// How the HTTP port bounds slow and numerous connections (http_connection.h),
// and whom it believes about a client's address.
void AddHttpConnectionFlags(CLI::App& app, ServerConfig& c) {
  Limits& limits = c.limits;
  app.add_option("--http-head-timeout", limits.http_head_timeout_seconds,
                 "Seconds an HTTP request's head (TLS handshake, request line, headers) may take in all")
      ->envname("ARMATURE_HTTP_HEAD_TIMEOUT")
      ->check(CLI::Range(0.1, 3600.0));
  app.add_option("--http-max-connections-per-address", limits.max_http_connections_per_address,
                 "Most HTTP connections one client address may hold open (each SSE stream or WebSocket holds one)")
      ->envname("ARMATURE_HTTP_MAX_CONNECTIONS_PER_ADDRESS")
      ->check(CLI::PositiveNumber);
  app.add_option("--trust-forwarded-for", c.trusted_proxies,
                 "Proxy address or network (e.g. 10.0.0.0/8; repeatable) whose X-Forwarded-For names the HTTP "
                 "client that per-client limits count; its own connections are not capped per address")
      ->envname("ARMATURE_TRUST_FORWARDED_FOR")
      ->delimiter(',')
      ->check([](const std::string& value) {
        auto cidr = gateway::ParseCidr(value);
        return cidr.ok() ? std::string() : std::string(cidr.status().message());
      });
}

}  // namespace

namespace {

// The bounds on what imports may hold: assets in memory, uploads at once.
// Returns the --max-assets-mb and --max-image-mb values to convert after parsing.
std::pair<std::shared_ptr<double>, std::shared_ptr<double>> AddMemoryFlags(CLI::App& app, Limits& limits) {
  auto assets_mb = std::make_shared<double>(static_cast<double>(limits.max_assets_bytes) / (1 << 20));
  auto image_mb = std::make_shared<double>(static_cast<double>(limits.max_image_bytes) / (1 << 20));
  app.add_option("--max-assets-mb", *assets_mb,
                 "Memory the loaded assets may take in all (estimated, as in armature_assets_memory_bytes), in "
                 "MiB; an import or new clip that would pass it is refused")
      ->envname("ARMATURE_MAX_ASSETS_MB")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-concurrent-uploads", limits.max_concurrent_uploads,
                 "Most imports (ImportAsset over gRPC, REST or gRPC-Web) received at once; more are refused")
      ->envname("ARMATURE_MAX_CONCURRENT_UPLOADS")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-image-mb", *image_mb,
                 "Largest material image (texture) an import keeps, in MiB, as stored (PNG or JPEG bytes); an import "
                 "with a larger one is refused")
      ->envname("ARMATURE_MAX_IMAGE_MB")
      ->check(CLI::PositiveNumber);
  return {assets_mb, image_mb};
}

// The bounds on what one import holds and what one IK request may ask.
void AddImportAndIkFlags(CLI::App& app, Limits& limits) {
  app.add_option("--max-clip-frames", limits.max_clip_frames, "Most frames an imported clip may have")
      ->envname("ARMATURE_MAX_CLIP_FRAMES")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-mesh-vertices", limits.max_mesh_vertices, "Most vertices an imported mesh may have")
      ->envname("ARMATURE_MAX_MESH_VERTICES")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-ik-iterations", limits.max_ik_iterations, "Most solver iterations an IK request may ask for")
      ->envname("ARMATURE_MAX_IK_ITERATIONS")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-ik-effectors", limits.max_ik_effectors, "Most effectors one IK request may have")
      ->envname("ARMATURE_MAX_IK_EFFECTORS")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-ik-work", limits.max_ik_work,
                 "Most work one IK request may ask for: the sum over its effectors of the joints in each "
                 "effector's chain, times max_iterations")
      ->envname("ARMATURE_MAX_IK_WORK")
      ->check(CLI::PositiveNumber);
}

// The caps on open streams and sessions, per client and in all.
void AddStreamAndSessionFlags(CLI::App& app, Limits& limits) {
  app.add_option("--max-sessions-per-client", limits.max_sessions_per_client,
                 "Most IK/deformation sessions one client may hold open")
      ->envname("ARMATURE_MAX_SESSIONS_PER_CLIENT")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-streams-per-client", limits.max_streams_per_client,
                 "Most streams (StreamClip, StreamSkinnedMesh, IkSession, DeformSession) one client may hold open")
      ->envname("ARMATURE_MAX_STREAMS_PER_CLIENT")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-streams", limits.max_streams,
                 "Most streams open at once, all clients together (each client also: --max-streams-per-client)")
      ->envname("ARMATURE_MAX_STREAMS")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-sessions", limits.max_sessions, "Most IK/deformation sessions open at once in all")
      ->envname("ARMATURE_MAX_SESSIONS")
      ->check(CLI::PositiveNumber);
  app.add_option("--crowd-budget-ms", limits.crowd_budget_ms,
                 "A crowd session's work budget per tick, in milliseconds: its default and the most a session may ask; "
                 "less significant characters are updated less often to keep within it")
      ->envname("ARMATURE_CROWD_BUDGET_MS")
      ->check(CLI::Range(0.01, 1000.0));
  app.add_option("--max-crowd-characters", limits.max_crowd_characters, "Most characters one crowd session may hold")
      ->envname("ARMATURE_MAX_CROWD_CHARACTERS")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-crowd-characters-total", limits.max_crowd_characters_total,
                 "Most characters every crowd session together may hold")
      ->envname("ARMATURE_MAX_CROWD_CHARACTERS_TOTAL")
      ->check(CLI::PositiveNumber);
  app.add_option("--crowd-write-timeout-seconds", limits.crowd_write_timeout_seconds,
                 "A crowd session whose frame stays unwritten this long (a client that stops reading) is dropped")
      ->envname("ARMATURE_CROWD_WRITE_TIMEOUT_SECONDS")
      ->check(CLI::Range(0.1, 3600.0));
  app.add_option("--max-ik-sessions", limits.max_ik_sessions, "Most IK sessions open at once, all clients together")
      ->envname("ARMATURE_MAX_IK_SESSIONS")
      ->check(CLI::NonNegativeNumber);
}

void AddStoreFlags(CLI::App& app, ServerConfig& c) {
  app.add_option("--store", c.store,
                 "Keep the assets on an S3 bucket, the data dir its local cache: s3://HOST:PORT/BUCKET/PREFIX "
                 "(HTTP) or s3+https://HOST[:PORT]/BUCKET/PREFIX; credentials from AWS_ACCESS_KEY_ID, "
                 "AWS_SECRET_ACCESS_KEY, AWS_SESSION_TOKEN, AWS_REGION or ~/.aws/credentials")
      ->envname("ARMATURE_STORE");
  app.add_option("--store-poll-ms", c.store_poll_ms, "How often the bucket is listed for other replicas' writes")
      ->envname("ARMATURE_STORE_POLL_MS")
      ->check(CLI::Range(50, 3600000));
  app.add_option("--store-keep-versions", c.store_keep_versions,
                 "Versions of each asset kept on the bucket (0: every one)")
      ->envname("ARMATURE_STORE_KEEP_VERSIONS")
      ->check(CLI::NonNegativeNumber);
}

}  // namespace

int ParseConfig(int argc, char** argv, ServerConfig& c) {
  CLI::App app{"armature-server: an animation server (pose evaluation, IK, skinning, deformation) over gRPC and HTTP"};
  app.option_defaults()->always_capture_default();
  app.set_version_flag("--version", build_info::VersionLine("armature-server"),
                       "Print the version and git commit, then exit");
  app.add_option("--host", c.host, "Address to listen on (0.0.0.0: every interface; then set --auth-token-file)")
      ->envname("ARMATURE_HOST");
  app.add_option("--grpc-port", c.grpc_port, "gRPC port (0: any free port)")
      ->envname("ARMATURE_GRPC_PORT")
      ->check(CLI::Range(0, 65535));
  app.add_option("--http-port", c.http_port, "HTTP port for health, gateway and viewer (0: any free port, -1: off)")
      ->envname("ARMATURE_HTTP_PORT")
      ->check(CLI::Range(-1, 65535));
  app.add_option("--data-dir", c.data_dir, "Where imported assets are persisted (with --store: its cache)")
      ->envname("ARMATURE_DATA_DIR");
  AddStoreFlags(app, c);
  app.add_option("--log-level", c.log_level, "trace, debug, info, warn or error")
      ->envname("ARMATURE_LOG_LEVEL")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}));
  app.add_option("--log-format", c.log_format, "text or json")
      ->envname("ARMATURE_LOG_FORMAT")
      ->check(CLI::IsMember({"text", "json"}));
  double upload_mb = static_cast<double>(c.limits.max_upload_bytes) / (1 << 20);
  app.add_option("--max-upload-mb", upload_mb, "Largest accepted upload, in MiB")
      ->envname("ARMATURE_MAX_UPLOAD_MB")
      ->check(CLI::PositiveNumber);
  double message_mb = static_cast<double>(c.limits.max_message_bytes) / (1 << 20);
  app.add_option("--max-message-mb", message_mb, "Largest gRPC message sent or received, in MiB")
      ->envname("ARMATURE_MAX_MESSAGE_MB")
      ->check(CLI::PositiveNumber);
  bool no_demo = !c.demo;
  app.add_flag("--no-demo", no_demo, "Do not seed demo assets into an empty data dir")->envname("ARMATURE_NO_DEMO");
  app.add_option("--shutdown-grace", c.shutdown_grace_seconds,
                 "Seconds in-flight calls get to finish on SIGTERM/SIGINT")
      ->envname("ARMATURE_SHUTDOWN_GRACE")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--port-file", c.port_file, "Write the bound ports as JSON here once serving")
      ->envname("ARMATURE_PORT_FILE");
  app.add_option("--cors-origin", c.cors_origins,
                 "Origin allowed to call the REST API from a browser, e.g. http://localhost:5173 (repeatable; * = any)")
      ->envname("ARMATURE_CORS_ORIGIN")
      ->delimiter(',');
  double request_kb = static_cast<double>(c.limits.max_request_bytes) / 1024;
  app.add_option("--max-request-kb", request_kb, "Largest REST JSON request body, in KiB (imports: --max-upload-mb)")
      ->envname("ARMATURE_MAX_REQUEST_KB")
      ->check(CLI::PositiveNumber);
  app.add_option("--http-threads", c.limits.max_http_threads,
                 "Most HTTP connections served at once (each open SSE stream holds one)")
      ->envname("ARMATURE_HTTP_THREADS")
      ->check(CLI::Range(16, 10000));
  AddHttpConnectionFlags(app, c);
  app.add_option("--web-dir", c.web_dir, "The viewer's files, served at / (default: the installed or built viewer)")
      ->envname("ARMATURE_WEB_DIR");
  app.add_option("--auth-token-file", c.auth_token_file,
                 "Require 'authorization: Bearer <token>' on API calls; one accepted token per line "
                 "(health checks and reflection stay open)")
      ->envname("ARMATURE_AUTH_TOKEN_FILE")
      ->check(CLI::ExistingFile);
  auto* cert = app.add_option("--tls-cert", c.tls_cert_file, "PEM certificate chain: serve gRPC and HTTP over TLS")
                   ->envname("ARMATURE_TLS_CERT")
                   ->check(CLI::ExistingFile);
  auto* key = app.add_option("--tls-key", c.tls_key_file, "PEM private key of --tls-cert")
                  ->envname("ARMATURE_TLS_KEY")
                  ->check(CLI::ExistingFile);
  cert->needs(key);
  key->needs(cert);
  AddImportAndIkFlags(app, c.limits);
  AddStreamAndSessionFlags(app, c.limits);
  double deform_cache_mb = static_cast<double>(c.limits.deform_cache_bytes) / (1 << 20);
  app.add_option("--deform-cache-mb", deform_cache_mb,
                 "Memory for factorizations kept between unary Deform calls with the same mesh, setup and "
                 "handle indices, in MiB (0: none)")
      ->envname("ARMATURE_DEFORM_CACHE_MB")
      ->check(CLI::NonNegativeNumber);
  AddWorkBudgetFlags(app, c.limits);
  const auto [assets_mb, image_mb] = AddMemoryFlags(app, c.limits);
  std::string clip_error = ClipPrecisionText(c.clip_precision);
  app.add_option("--clip-error", clip_error,
                 "How closely clips are kept unless an import asks: a bound in centimetres on points 3 cm from "
                 "each joint, in (0, 10], or 'exact' (the stored keys bit for bit)")
      ->envname("ARMATURE_CLIP_ERROR")
      ->check([](const std::string& text) {
        const auto parsed = ParseClipPrecision(text, "--clip-error");
        return parsed.ok() ? std::string() : parsed.status().message();
      });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  c.demo = !no_demo;
  c.clip_precision = *ParseClipPrecision(clip_error, "--clip-error");
  c.limits.max_upload_bytes = static_cast<int64_t>(upload_mb * (1 << 20));
  c.limits.max_message_bytes = static_cast<int64_t>(message_mb * (1 << 20));
  c.limits.max_request_bytes = static_cast<int64_t>(request_kb * 1024);
  c.limits.deform_cache_bytes = static_cast<int64_t>(deform_cache_mb * (1 << 20));
  c.limits.max_assets_bytes = static_cast<int64_t>(*assets_mb * (1 << 20));
  c.limits.max_image_bytes = static_cast<int64_t>(*image_mb * (1 << 20));
  return -1;
}

bool IsLoopbackHost(const std::string& host) {
  return host == "localhost" || host == "::1" || host == "[::1]" || host.rfind("127.", 0) == 0;
}

std::string DefaultWebDir() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "";
  const fs::path dir = exe.parent_path().parent_path() / "share" / "armature" / "web";
  return fs::exists(dir / "index.html", ec) ? dir.string() : "";
}

}  // namespace armature::server
