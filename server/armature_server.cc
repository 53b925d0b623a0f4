#include "server/armature_server.h"

#include <chrono>
#include <fstream>

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>
#include <spdlog/spdlog.h>

#include "grpc/health/v1/health.pb.h"
#include "server/demo_assets.h"
#include "server/services.h"

namespace armature::server {

StatusOr<std::unique_ptr<ArmatureServer>> ArmatureServer::Start(const ServerConfig& config) {
  std::unique_ptr<ArmatureServer> s(new ArmatureServer());
  s->config_ = config;

  auto store = AssetStore::Open(config.data_dir);
  if (!store.ok()) return store.status();
  s->store_ = std::move(*store);
  if (s->store_->fresh() && config.demo) {
    if (Status st = SeedDemoAssets(*s->store_); !st.ok())
      spdlog::error("could not seed the demo assets: {}", st.message());
    else
      spdlog::info("seeded demo assets into {}", s->store_->data_dir().string());
  }

  grpc::EnableDefaultHealthCheckService(true);
  // Links health.proto's descriptor in, so reflection can describe the health service.
  (void)grpc::health::v1::HealthCheckRequest::descriptor();
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  builder.AddListeningPort(config.host + ":" + std::to_string(config.grpc_port), grpc::InsecureServerCredentials(),
                           &s->grpc_port_);
  builder.SetMaxReceiveMessageSize(static_cast<int>(config.limits.max_message_bytes));
  builder.SetMaxSendMessageSize(static_cast<int>(config.limits.max_message_bytes));
  s->services_ = MakeServices(*s->store_, s->config_.limits);
  for (auto& service : s->services_) builder.RegisterService(service.get());
  s->grpc_ = builder.BuildAndStart();
  if (!s->grpc_ || s->grpc_port_ == 0)
    return Status::Unavailable("cannot listen for gRPC on " + config.host + ":" + std::to_string(config.grpc_port));
  s->grpc_->GetHealthCheckService()->SetServingStatus(true);

  if (config.http_port >= 0) {
    s->http_ = std::make_unique<HttpServer>();
    s->http_port_ = s->http_->Start(config.host, config.http_port);
    if (s->http_port_ < 0)
      return Status::Unavailable("cannot listen for HTTP on " + config.host + ":" + std::to_string(config.http_port));
    s->http_->SetReady(true);
  }
  spdlog::info("serving gRPC on {}:{} and HTTP on {}:{}", config.host, s->grpc_port_, config.host, s->http_port_);

  if (!config.port_file.empty()) {
    const std::string tmp = config.port_file + ".tmp";
    std::ofstream(tmp) << "{\"grpc\":" << s->grpc_port_ << ",\"http\":" << s->http_port_ << "}\n";
    std::rename(tmp.c_str(), config.port_file.c_str());
  }
  return s;
}

void ArmatureServer::Shutdown() {
  if (stopped_) return;
  stopped_ = true;
  spdlog::info("shutting down: finishing in-flight calls (up to {} s)", config_.shutdown_grace_seconds);
  if (http_) http_->SetReady(false);
  grpc_->GetHealthCheckService()->SetServingStatus(false);
  grpc_->Shutdown(std::chrono::system_clock::now() +
                  std::chrono::milliseconds(static_cast<int64_t>(config_.shutdown_grace_seconds * 1000)));
  spdlog::debug("gRPC shut down");
  if (http_) http_->Stop();
  spdlog::debug("HTTP stopped");
  grpc_->Wait();
  spdlog::info("stopped");
}

ArmatureServer::~ArmatureServer() { Shutdown(); }

}  // namespace armature::server
