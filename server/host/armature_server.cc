#include "server/host/armature_server.h"

#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <thread>

#include <absl/synchronization/mutex.h>
#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>
#include <httplib.h>
#include <spdlog/spdlog.h>

#include "grpc/health/v1/health.pb.h"
#include "server/host/gateway/rest/transcoding/http_rule.h"
#include "server/assets/asset_memory.h"
#include "server/assets/bucket/s3_client.h"
#include "server/host/auth/auth_gate.h"
#include "server/host/http/listen_error.h"
#include "server/assets/demo_assets.h"
#include "server/host/observability/metrics_http.h"
#include "server/host/reflection_v1_service.h"
#include "server/host/observability/rpc_observer.h"
#include "server/host/server_credentials.h"
#include "server/host/services.h"

namespace armature::server {
namespace {
// How long past --shutdown-grace the process waits for handlers to return.
constexpr std::chrono::seconds kShutdownMargin{3};
}  // namespace

StatusOr<std::unique_ptr<ArmatureServer>> ArmatureServer::Start(const ServerConfig& config) {
  std::unique_ptr<ArmatureServer> s(new ArmatureServer());
  s->config_ = config;
  ARMATURE_RETURN_IF_ERROR(s->LoadAccessRules());
  ARMATURE_ASSIGN_OR_RETURN(std::shared_ptr<grpc::ServerCredentials> credentials, MakeServerCredentials(config));
  ARMATURE_RETURN_IF_ERROR(s->OpenStore());
  ARMATURE_RETURN_IF_ERROR(s->StartGrpc(credentials));
  if (config.http_port >= 0) ARMATURE_RETURN_IF_ERROR(s->StartHttp());
  spdlog::info("serving gRPC on {}:{} and HTTP on {}:{}{}{}", config.host, s->grpc_port_, config.host, s->http_port_,
               config.tls_cert_file.empty() ? "" : " (TLS)", s->tokens_ ? ", bearer token required" : "");
  if (!s->tokens_ && !IsLoopbackHost(config.host))
    spdlog::warn(
        "listening on {} beyond this machine with no --auth-token-file: anyone who reaches these ports "
        "can import, delete and call everything; set --auth-token-file, or --host 127.0.0.1",
        config.host);

  if (!config.port_file.empty()) {
    const std::string tmp = config.port_file + ".tmp";
    std::ofstream(tmp) << "{\"grpc\":" << s->grpc_port_ << ",\"http\":" << s->http_port_ << "}\n";
    std::rename(tmp.c_str(), config.port_file.c_str());
  }
  return s;
}

Status ArmatureServer::LoadAccessRules() {
  if (!config_.auth_token_file.empty()) {
    ARMATURE_ASSIGN_OR_RETURN(tokens_, BearerTokens::FromFile(config_.auth_token_file));
    for (int line : tokens_->lines_browsers_cannot_send())
      spdlog::warn(
          "{}:{}: this token has characters outside A-Z a-z 0-9 and !#$%&'*+-.^_`|~ ('/' or '=' of "
          "base64, say): browsers cannot send it as a WebSocket subprotocol; make tokens with "
          "'openssl rand -hex 32'",
          config_.auth_token_file, line);
  }
  std::vector<gateway::Cidr> proxies;
  for (const std::string& text : config_.trusted_proxies) {
    ARMATURE_ASSIGN_OR_RETURN(gateway::Cidr cidr, gateway::ParseCidr(text));
    proxies.push_back(cidr);
  }
  trusted_proxies_ = gateway::TrustedProxies(std::move(proxies));
  return Status::Ok();
}

Status ArmatureServer::OpenStore() {
  StoreOptions options{.limits = config_.limits, .clip_precision = config_.clip_precision};
  if (!config_.store.empty()) {
    ARMATURE_ASSIGN_OR_RETURN(StoreLocation location, ParseStoreUrl(config_.store));
    ARMATURE_ASSIGN_OR_RETURN(AwsCredentials credentials, LoadAwsCredentials());
    spdlog::info("asset store: bucket {}, credentials from {}, region {}, cache in {}", location.Describe(),
                 credentials.source, credentials.region, config_.data_dir);
    const std::string prefix = location.prefix;
    options.bucket =
        std::make_shared<BucketMirror>(std::make_unique<S3Client>(std::move(location), std::move(credentials)), prefix);
    options.watch_interval = std::chrono::milliseconds(config_.store_poll_ms);
    options.keep_versions = config_.store_keep_versions;
  }
  ARMATURE_ASSIGN_OR_RETURN(store_, AssetStore::Open(config_.data_dir, std::move(options)));
  if (store_->fresh() && config_.demo) {
    if (Status st = SeedDemoAssets(*store_); !st.ok())
      spdlog::error("could not seed the demo assets: {}", st.message());
    else
      spdlog::info("seeded demo assets into {}", store_->data_dir().string());
  }
  return Status::Ok();
}

Status ArmatureServer::StartGrpc(const std::shared_ptr<grpc::ServerCredentials>& credentials) {
  // gRPC's locks are absl::Mutex, and the distribution's absl is built with
  // deadlock detection on: a lock-order graph updated on every lock, about a
  // tenth of a loaded server's CPU (measured with bench/load). Off, as in
  // absl's release builds.
  absl::SetMutexDeadlockDetectionMode(absl::OnDeadlockCycle::kIgnore);
  grpc::EnableDefaultHealthCheckService(true);
  // Links health.proto's descriptor in, so reflection can describe the health service.
  (void)grpc::health::v1::HealthCheckRequest::descriptor();
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  builder.AddListeningPort(config_.host + ":" + std::to_string(config_.grpc_port), credentials, &grpc_port_);
  // No SO_REUSEPORT (gRPC's default): a second server on the same port must fail, not split the traffic.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  builder.SetMaxReceiveMessageSize(static_cast<int>(config_.limits.max_message_bytes));
  builder.SetMaxSendMessageSize(static_cast<int>(config_.limits.max_message_bytes));
  // Every call, REST ones through the in-process channel included, passes the observer (metrics, request log).
  metrics_ = std::make_unique<Metrics>();
  metrics_->AddCollector([store = store_.get()](PrometheusText& out) {
    CollectAssetMetrics(*store->Snapshot(), out);
    CollectStoreMetrics(store->Health(), out);
  });
  std::vector<std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface>> interceptors;
  interceptors.push_back(std::make_unique<RpcObserverFactory>(*metrics_));
  builder.experimental().SetInterceptorCreators(std::move(interceptors));
  ARMATURE_ASSIGN_OR_RETURN(std::vector<std::string> service_names, AddServices());
  for (auto& service : services_) builder.RegisterService(service.get());
  grpc_ = builder.BuildAndStart();
  if (!grpc_ || grpc_port_ == 0) return Status::Unavailable(ListenError("gRPC", config_.host, config_.grpc_port));
  // grpc.health.v1 answers for "" (the whole server) and for each armature.v1 service by full name.
  for (const std::string& name : service_names) grpc_->GetHealthCheckService()->SetServingStatus(name, true);
  grpc_->GetHealthCheckService()->SetServingStatus(true);
  return Status::Ok();
}

StatusOr<std::vector<std::string>> ArmatureServer::AddServices() {
  // With a token file, each API service sits behind an auth gate; health and reflection (v1alpha, v1) stay open.
  std::vector<std::string> service_names;
  for (ServiceEntry& entry : MakeServices(*store_, config_.limits, *metrics_, tokens_ != nullptr)) {
    service_names.push_back(entry.name);
    if (tokens_) {
      ARMATURE_ASSIGN_OR_RETURN(entry.service, GateService(std::move(entry.service), entry.name, tokens_));
    }
    services_.push_back(std::move(entry.service));
  }
  // Reflection v1 beside the plugin's v1alpha, open like it; both list the same services.
  std::vector<std::string> reflected = service_names;
  reflected.insert(reflected.end(), {"grpc.health.v1.Health", "grpc.reflection.v1.ServerReflection",
                                     "grpc.reflection.v1alpha.ServerReflection"});
  services_.push_back(std::make_unique<ReflectionV1Service>(std::move(reflected)));
  return service_names;
}

Status ArmatureServer::StartHttp() {
  const Limits& limits = config_.limits;
  const HttpConnectionLimits connections{
      .head_timeout = std::chrono::milliseconds(static_cast<int64_t>(limits.http_head_timeout_seconds * 1000)),
      .max_per_address = limits.max_http_connections_per_address,
      .trusted_proxies = trusted_proxies_};
  http_ =
      std::make_unique<HttpServer>(limits.max_http_threads, config_.tls_cert_file, config_.tls_key_file, connections);
  ServeMetrics(http_->routes(), *metrics_, tokens_);
  http_->SetStoreHealth([store = store_.get()] { return StoreHealthJson(store->Health()); });
  ARMATURE_RETURN_IF_ERROR(StartGateway());
  http_port_ = http_->Start(config_.host, config_.http_port);
  if (http_port_ < 0) return Status::Unavailable(ListenError("HTTP", config_.host, config_.http_port));
  http_->SetReady(true);
  return Status::Ok();
}

Status ArmatureServer::StartGateway() {
  const Limits& limits = config_.limits;
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(static_cast<int>(limits.max_message_bytes));
  args.SetMaxSendMessageSize(static_cast<int>(limits.max_message_bytes));
  gateway::GatewayOptions options;
  options.cors_origins = config_.cors_origins;
  options.tokens = tokens_;
  options.trusted_proxies = trusted_proxies_;
  options.max_request_bytes = static_cast<size_t>(limits.max_request_bytes);
  options.max_upload_bytes = static_cast<size_t>(limits.max_upload_bytes);
  options.max_reply_bytes = static_cast<size_t>(limits.max_message_bytes);
  // Keep threads free for ordinary requests however many streams are open.
  options.max_streams = limits.max_http_threads - std::min<size_t>(limits.max_http_threads / 4, 64);
  ARMATURE_ASSIGN_OR_RETURN(gateway_, gateway::Gateway::Create(gateway::GeneratedServicesIn("armature.v1"),
                                                               google::protobuf::MessageFactory::generated_factory(),
                                                               grpc_->InProcessChannel(args), options));
  httplib::Server& routes = http_->routes();
  // A form upload's boundaries and part headers are not part of what --max-upload-mb counts: room for them.
  constexpr int64_t kFormFramingBytes = 1 << 20;
  routes.set_payload_max_length(
      static_cast<size_t>(std::max(limits.max_upload_bytes + kFormFramingBytes, limits.max_request_bytes)));
  // The viewer first: its /docs redirect goes before the gateway's catch-all.
  const std::string web_dir = config_.web_dir.empty() ? DefaultWebDir() : config_.web_dir;
  if (web_dir.empty())
    spdlog::warn("viewer: no built viewer found (build the armature_web target or pass --web-dir)");
  else if (!http_->ServeDirectory(web_dir))
    return Status::InvalidArgument("--web-dir " + web_dir + ": not a directory");
  else
    spdlog::info("viewer: serving {} at /", web_dir);
  gateway_->Register(routes);
  spdlog::info("REST gateway: {} routes; OpenAPI at /openapi.json", gateway_->bindings().size());

  return Status::Ok();
}

void ArmatureServer::Shutdown() {
  if (stopped_) return;
  stopped_ = true;
  if (!grpc_) return;  // Start failed before serving
  spdlog::info("shutting down: finishing in-flight calls (up to {} s)", config_.shutdown_grace_seconds);
  const auto deadline = std::chrono::system_clock::now() +
                        std::chrono::milliseconds(static_cast<int64_t>(config_.shutdown_grace_seconds * 1000));
  if (gateway_) gateway_->BeginDrain();  // before readiness drops, so /readyz 503 means REST refuses too
  if (http_) http_->SetReady(false);
  grpc_->GetHealthCheckService()->SetServingStatus(false);
  // REST calls ride the in-process channel, which the gRPC shutdown drops at
  // once: they get their grace period first.
  if (gateway_) gateway_->Drain(deadline);
  // Past the grace period gRPC cancels what is still in flight; a handler
  // that still does not return (stuck in work that checks no cancellation)
  // must not keep the process alive: the watchdog ends it.
  std::mutex mu;
  std::condition_variable cv;
  bool done = false;
  std::thread watchdog([&] {
    std::unique_lock lock(mu);
    if (cv.wait_until(lock, deadline + kShutdownMargin, [&] { return done; })) return;
    spdlog::error("shutdown: calls still running {} s after the grace period; exiting anyway",
                  std::chrono::duration_cast<std::chrono::seconds>(kShutdownMargin).count());
    spdlog::shutdown();
    std::_Exit(0);
  });
  grpc_->Shutdown(deadline);
  spdlog::debug("gRPC shut down");
  if (http_) http_->Stop();
  spdlog::debug("HTTP stopped");
  grpc_->Wait();
  {
    std::lock_guard lock(mu);
    done = true;
  }
  cv.notify_one();
  watchdog.join();
  spdlog::info("stopped");
}

ArmatureServer::~ArmatureServer() { Shutdown(); }

}  // namespace armature::server
