#include "server/host/observability/rpc_observer.h"

#include <array>
#include <chrono>
#include <cmath>
#include <random>

#include <google/protobuf/descriptor.h>
#include <spdlog/spdlog.h>

#include "server/rpc/grpc_status.h"
#include "server/host/observability/logging.h"

namespace armature::server {
namespace {

using grpc::experimental::InterceptionHookPoints;

std::string NewRequestId() {
  static thread_local std::mt19937_64 rng{std::random_device{}()};
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(rng()));
  return buf;
}

// A client's id is kept if it is short and printable, so it cannot forge log lines.
std::string RequestIdFrom(const std::multimap<grpc::string_ref, grpc::string_ref>& metadata) {
  const auto it = metadata.find("x-request-id");
  if (it == metadata.end() || it->second.empty() || it->second.size() > 128) return NewRequestId();
  std::string id(it->second.data(), it->second.size());
  for (char c : id)
    if (c < 0x21 || c > 0x7e) return NewRequestId();
  return id;
}

// The metric label of a method: itself when this binary knows it (a
// bounded set), else "unknown", so clients calling made-up methods cannot
// grow the label set without bound.
std::string MetricLabelOf(const std::string& method) {
  const auto slash = method.find('/');
  if (slash != std::string::npos) {
    const auto* service =
        google::protobuf::DescriptorPool::generated_pool()->FindServiceByName(method.substr(0, slash));
    if (service != nullptr && service->FindMethodByName(method.substr(slash + 1)) != nullptr) return method;
  }
  return "unknown";
}

class RpcObserver final : public grpc::experimental::Interceptor {
 public:
  RpcObserver(grpc::experimental::ServerRpcInfo* info, Metrics& metrics)
      : info_(info),
        metrics_(metrics),
        method_(info->method() == nullptr  ? ""
                : info->method()[0] == '/' ? info->method() + 1
                                           : info->method()),
        label_(MetricLabelOf(method_)),
        streaming_(info->type() != grpc::experimental::ServerRpcInfo::Type::UNARY),
        health_(method_.starts_with("grpc.health.v1.")) {}

  ~RpcObserver() override {
    // A call can end without sending a status (the client went away).
    if (started_ && !finished_) Finish(grpc::Status(grpc::StatusCode::CANCELLED, "ended without a status"));
  }

  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::POST_RECV_INITIAL_METADATA)) {
      start_ = std::chrono::steady_clock::now();
      request_id_ = RequestIdFrom(*methods->GetRecvInitialMetadata());
      peer_ = info_->server_context()->peer();  // now: the context is gone when a cancelled call ends
      started_ = true;
      metrics_.RpcStarted(label_, streaming_);
    }
    if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::PRE_SEND_INITIAL_METADATA) && !request_id_.empty())
      methods->GetSendInitialMetadata()->emplace("x-request-id", request_id_);
    if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::PRE_SEND_STATUS) && started_ && !finished_)
      Finish(methods->GetSendStatus());
    methods->Proceed();
  }

 private:
  void Finish(const grpc::Status& status) {
    finished_ = true;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const char* code = GrpcCodeName(status.error_code());
    metrics_.RpcFinished(label_, streaming_, code, seconds);
    // Health checks log at debug: most servers run above it, and building the
    // fields of a line nobody prints is the costliest part of a health check's
    // own work here.
    const auto level = health_ ? spdlog::level::debug : spdlog::level::info;
    if (!spdlog::should_log(level)) return;
    // In key order, as LogEvent's JSON object printed them.
    const double duration_ms = std::round(seconds * 1e6) / 1e3;
    const std::string error = status.error_message();  // returned by value: kept for the view below
    std::array<LogField, 6> fields;
    size_t n = 0;
    fields[n++] = {"code", std::string_view(code)};
    fields[n++] = {"duration_ms", duration_ms};
    if (!status.ok()) fields[n++] = {"error", std::string_view(error)};
    fields[n++] = {"method", std::string_view(method_)};
    fields[n++] = {"peer", std::string_view(peer_)};
    fields[n++] = {"request_id", std::string_view(request_id_)};
    LogFields(level, "rpc", std::span<const LogField>(fields.data(), n));
  }

  grpc::experimental::ServerRpcInfo* info_;
  Metrics& metrics_;
  std::string method_;  // "armature.v1.PoseService/EvaluateClip", as called
  std::string label_;   // method_ or "unknown"
  bool streaming_;
  bool health_;
  bool started_ = false;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
  std::string request_id_;
  std::string peer_;
};

}  // namespace

grpc::experimental::Interceptor* RpcObserverFactory::CreateServerInterceptor(grpc::experimental::ServerRpcInfo* info) {
  return new RpcObserver(info, metrics_);
}

}  // namespace armature::server
