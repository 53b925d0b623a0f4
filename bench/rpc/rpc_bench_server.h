// One in-process armature-server (gRPC and HTTP on free ports, demo assets, the CMU
// capture when present) and a client, shared by the *_rpc_bench.cc files.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <memory>
#include <stdexcept>

#include "armature/client.h"
#include "server/host/armature_server.h"
#include "server/host/observability/logging.h"

namespace armature_bench {
namespace fs = std::filesystem;

struct BenchServer {
  fs::path dir;
  std::unique_ptr<armature::server::ArmatureServer> server;
  std::unique_ptr<armature::client::Client> client;
  bool has_cmu = false;

  BenchServer() {
    dir = fs::temp_directory_path() / ("armature-bench-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    armature::server::ServerConfig config;
    config.host = "127.0.0.1";
    config.grpc_port = 0;
    config.http_port = 0;  // gRPC-Web and REST (grpc_web_rpc_bench.cc)
    config.data_dir = dir.string();
    config.log_level = "warn";  // no per-call request log lines in the measurement
    armature::server::ConfigureLogging(config.log_level, config.log_format);
    auto started = armature::server::ArmatureServer::Start(config);
    if (!started.ok()) throw std::runtime_error(started.status().message());
    server = std::move(*started);
    armature::client::ClientOptions o;
    o.target = "127.0.0.1:" + std::to_string(server->grpc_port());
    client = std::make_unique<armature::client::Client>(o);
    const fs::path cmu = fs::path(ARMATURE_SHARED_DATA) / "bvh" / "cmu_01_01.bvh";
    if (fs::exists(cmu)) {
      client->ImportFile(cmu, "cmu");
      has_cmu = true;
    }
  }
  ~BenchServer() {
    client.reset();
    server.reset();
    fs::remove_all(dir);
  }
};

inline BenchServer& Server() {
  static BenchServer s;
  return s;
}

}  // namespace armature_bench
