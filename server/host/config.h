// armature-server's settings, from flags and ARMATURE_* environment variables.
#pragma once

#include <string>
#include <vector>

#include "armature/engine/anim/compression/error_bound.h"
#include "server/rpc/limits.h"

namespace armature::server {

struct ServerConfig {
  std::string host = "127.0.0.1";          // this machine only; the image and Kubernetes set 0.0.0.0
  int grpc_port = 50051;                   // 0 picks a free port
  int http_port = 8080;                    // 0 picks a free port; -1 disables HTTP
  std::string data_dir = "armature-data";  // with --store: the bucket's local cache
  std::string store;                       // s3://HOST:PORT/BUCKET/PREFIX (or s3+https://); empty: the data dir only
  int store_poll_ms = 1000;                // how often the bucket is listed for other replicas' writes
  int store_keep_versions = 0;             // versions kept per asset on the bucket; 0: every one
  std::string log_level = "info";          // trace, debug, info, warn, error
  std::string log_format = "text";         // text or json
  bool demo = true;                        // seed demo assets into an empty data dir
  double shutdown_grace_seconds = 10;
  std::string port_file;                  // when set, {"grpc":…,"http":…} is written there once serving
  std::vector<std::string> cors_origins;  // origins allowed to call the REST gateway from a browser ("*": any)
  std::string web_dir;                    // the viewer's files; empty: the installed or built location (DefaultWebDir)
  std::string auth_token_file;            // when set, API calls need "authorization: Bearer <a token in it>"
  std::string tls_cert_file;              // PEM certificate chain: TLS on the gRPC and HTTP ports
  std::string tls_key_file;               // PEM private key of tls_cert_file
  std::vector<std::string> trusted_proxies;  // --trust-forwarded-for: networks whose X-Forwarded-For is believed
  ClipPrecision clip_precision;              // --clip-error: imports' clips' precision unless they ask
  Limits limits;
};

// Parses argv (CLI11). Returns an exit code >= 0 when the process should
// exit (e.g. --help printed, or a bad flag), -1 to go on.
int ParseConfig(int argc, char** argv, ServerConfig& config);

// True for an address only this machine reaches: 127.0.0.0/8, ::1, localhost.
bool IsLoopbackHost(const std::string& host);

// Where the viewer's files are when --web-dir is not given:
// <the binary's dir>/../share/armature/web, which is where both the build
// tree (build/bin, build/share) and an install put them. Empty when absent.
std::string DefaultWebDir();

}  // namespace armature::server
