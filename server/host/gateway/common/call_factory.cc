#include "server/host/gateway/common/call_factory.h"

#include <algorithm>
#include <cctype>
#include <optional>

#include <httplib.h>

#include "server/rpc/caller_identity.h"  // kRestPeerMetadata

namespace armature::server::gateway {
namespace {

// HTTP headers that travel to the gRPC handlers as metadata.
constexpr const char* kForwardedHeaders[] = {"authorization", "x-request-id", "traceparent", "tracestate"};

// gRPC's timeout header: up to 8 digits and a unit (H, M, S, m, u, n).
std::optional<std::chrono::nanoseconds> ParseGrpcTimeout(const std::string& text) {
  if (text.size() < 2 || text.size() > 9) return std::nullopt;
  int64_t value = 0;
  for (size_t i = 0; i + 1 < text.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(text[i]))) return std::nullopt;
    value = value * 10 + (text[i] - '0');
  }
  using namespace std::chrono;
  switch (text.back()) {
    case 'H': return hours(value);
    case 'M': return minutes(value);
    case 'S': return seconds(value);
    case 'm': return milliseconds(value);
    case 'u': return microseconds(value);
    case 'n': return nanoseconds(value);
    default: return std::nullopt;
  }
}

bool IsPrintableAscii(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](unsigned char c) { return c >= 0x20 && c < 0x7f; });
}

}  // namespace

CallFactory::CallFactory(GatewayOptions options, google::protobuf::MessageFactory* factory,
                         std::shared_ptr<grpc::Channel> channel)
    : options_(std::move(options)),
      factory_(factory),
      channel_(std::move(channel)),
      stub_(std::make_unique<grpc::GenericStub>(channel_)) {}

grpc::Status CallFactory::Authenticate(const std::string& authorization) const {
  if (!options_.tokens) return grpc::Status::OK;
  if (Status st = options_.tokens->Check(authorization); !st.ok())
    return grpc::Status(grpc::StatusCode::UNAUTHENTICATED, st.message());
  return grpc::Status::OK;
}

grpc::Status CallFactory::MakeContext(const httplib::Request& req, bool server_streaming,
                                      std::unique_ptr<grpc::ClientContext>* context) const {
  auto ctx = std::make_unique<grpc::ClientContext>();
  std::optional<std::chrono::nanoseconds> timeout;
  if (req.has_header("grpc-timeout")) {
    timeout = ParseGrpcTimeout(req.get_header_value("grpc-timeout"));
    if (!timeout)
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          "header grpc-timeout: expected up to 8 digits and a unit H, M, S, m, u or n, e.g. 500m");
  } else if (!server_streaming) {
    timeout = options_.default_timeout;
  }
  if (timeout)
    ctx->set_deadline(std::chrono::system_clock::now() +
                      std::chrono::duration_cast<std::chrono::system_clock::duration>(*timeout));
  for (const char* name : kForwardedHeaders) {
    if (!req.has_header(name)) continue;
    const std::string value = req.get_header_value(name);
    if (!IsPrintableAscii(value))
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          std::string("header ") + name + ": must be printable ASCII");
    ctx->AddMetadata(name, value);
  }
  // Per-client limits (streams, sessions) count each HTTP client apart; behind
  // a trusted proxy, the client it names.
  std::string forwarded_for;
  for (size_t i = 0; i < req.get_header_value_count("X-Forwarded-For"); ++i) {
    if (i > 0) forwarded_for += ',';  // appended apart: GCC 12's false -Wrestrict on "," + std::string&&
    forwarded_for += req.get_header_value("X-Forwarded-For", i);
  }
  ctx->AddMetadata(kRestPeerMetadata, options_.trusted_proxies.ClientOf(req.remote_addr, forwarded_for));
  *context = std::move(ctx);
  return grpc::Status::OK;
}

grpc::Status CallFactory::CallWhole(const std::string& method, std::unique_ptr<grpc::ClientContext> context,
                                    std::vector<std::string> requests, std::vector<std::string>* responses) {
  auto call = GenericCall::Start(*stub_, method, std::move(context), std::move(requests));
  if (!calls_.Add(call.get())) return ShuttingDown();
  const grpc::Status status = call->Drain(responses);
  calls_.Remove(call.get());
  return status;
}

grpc::Status CallFactory::StartUpload(const std::string& method, std::unique_ptr<grpc::ClientContext> context,
                                      std::unique_ptr<GenericCall>* call) {
  *call = GenericCall::StartWriting(*stub_, method, std::move(context));
  if (!calls_.Add(call->get())) return ShuttingDown();
  return grpc::Status::OK;
}

grpc::Status CallFactory::TakeStreamSlot(const std::string& what) {
  if (open_streams_.fetch_add(1) < options_.max_streams) return grpc::Status::OK;
  --open_streams_;
  return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                      "too many open " + what + " (" + std::to_string(options_.max_streams) + "); try again later");
}

grpc::Status CallFactory::StartStream(const std::string& method, std::unique_ptr<grpc::ClientContext> context,
                                      std::vector<std::string> requests, std::shared_ptr<GenericCall>* call) {
  if (grpc::Status st = TakeStreamSlot("streams"); !st.ok()) return st;
  *call = GenericCall::Start(*stub_, method, std::move(context), std::move(requests));
  return RegisterInSlot(*call);
}

grpc::Status CallFactory::StartSession(const std::string& method, std::unique_ptr<grpc::ClientContext> context,
                                       std::unique_ptr<BidiCall>* call) {
  if (grpc::Status st = TakeStreamSlot("streams and sessions"); !st.ok()) return st;
  *call = BidiCall::Start(*stub_, method, std::move(context));
  return RegisterInSlot(*call);
}

}  // namespace armature::server::gateway
