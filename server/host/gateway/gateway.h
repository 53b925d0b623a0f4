// The REST/JSON gateway: one generic transcoder over every RPC that carries a
// (google.api.http) rule. Each HTTP request is matched against the compiled
// path templates, turned into request messages (transcoder.h) and sent to the
// server's own gRPC services through an in-process channel, so whatever the
// gRPC side checks (validation, limits, the auth gate, metrics) applies to
// REST as well. A new annotated RPC needs no code here.
#pragma once

#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>

#include "armature/base/status.h"
#include "server/host/bearer_tokens.h"
#include "server/host/gateway/call_registry.h"
#include "server/host/gateway/cors.h"
#include "server/host/gateway/forwarded_for.h"
#include "server/host/gateway/http_rule.h"
#include "server/host/gateway/transcoder.h"

namespace httplib {
class Server;
struct Request;
struct Response;
class ContentReader;
}  // namespace httplib

namespace armature::server::gateway {

// The request's Content-Type without parameters, lower case, no spaces.
std::string MediaType(const httplib::Request& req);
// True when the request asks for `Upgrade: websocket` (websocket_session.cc).
bool IsWebSocketUpgrade(const httplib::Request& req);

class BidiCall;

// How much of a refused body is still read (and dropped) past the limit, so
// the connection stays in step for the next request.
inline constexpr size_t kDrainBytes = 64u << 20;
// UNAVAILABLE: the server is shutting down.
grpc::Status ShuttingDown();
// "request body: <size> bytes exceed the limit of <limit> bytes (--max-upload-mb)"
// (or --max-request-kb when not `raw`).
std::string TooLarge(size_t size, size_t limit, bool raw);

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
  size_t max_streams = 200;  // open SSE and gRPC-Web streams and WebSocket sessions; more are refused (each holds an HTTP thread)
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

class Gateway {
 public:
  // Compiles the bindings of every method of `services`. INVALID_ARGUMENT for
  // a malformed rule or two methods claiming the same HTTP method and path.
  // `factory` makes the request and response messages (generated or dynamic).
  static StatusOr<std::unique_ptr<Gateway>> Create(const std::vector<const google::protobuf::ServiceDescriptor*>& services,
                                                   google::protobuf::MessageFactory* factory,
                                                   std::shared_ptr<grpc::Channel> channel, GatewayOptions options);

  // Adds CORS, OPTIONS, /openapi.json, gRPC-Web (POST /armature.v1.<Service>/<Method>,
  // every method of `services`) and the REST routes to `http`. Routes
  // registered before stay first; static files still win for GET.
  void Register(httplib::Server& http);

  // Shutdown, first step: new REST calls get 503 from now on.
  void BeginDrain() { calls_.BeginDrain(); }
  // Lets the calls in flight finish until `deadline`, then cancels the rest.
  // Call before shutting the gRPC server down, which drops in-process calls.
  void Drain(std::chrono::system_clock::time_point deadline) { calls_.Drain(deadline); }

  const std::vector<HttpBinding>& bindings() const { return bindings_; }

 private:
  struct Route {
    const HttpBinding* binding = nullptr;
    PathBindings variables;
  };

  Gateway(GatewayOptions options, google::protobuf::MessageFactory* factory, std::shared_ptr<grpc::Channel> channel);
  std::vector<Route> BestMatches(const RequestPath& path) const;
  std::optional<Route> Match(const std::string& http_method, const RequestPath& path) const;
  std::string AllowedMethods(const RequestPath& path) const;  // "GET, DELETE" or ""
  size_t BodyLimit(const HttpBinding& binding, const std::string& content_type) const;
  grpc::Status MakeContext(const httplib::Request& req, bool server_streaming,
                           std::unique_ptr<grpc::ClientContext>* context) const;

  void Handle(const httplib::Request& req, httplib::Response& res, const httplib::ContentReader* reader);
  // A multipart/form-data upload into `requests` (multipart_upload.h); false
  // once it has written the error.
  bool ReadMultipartUpload(const HttpBinding& binding, const httplib::ContentReader* reader, uint64_t declared,
                           const HttpRequestParts& http, httplib::Response& res, std::vector<std::string>* requests);
  // Sends `requests` to the binding's method and writes its answer.
  void Dispatch(const httplib::Request& req, const HttpBinding& binding, std::vector<std::string> requests,
                httplib::Response& res);
  void CallUnary(const HttpBinding& binding, std::unique_ptr<grpc::ClientContext> context,
                 std::vector<std::string> requests, bool proto_response, httplib::Response& res);
  // Writes a unary or client-streaming call's answer: its one response as
  // JSON (or protobuf), or its error.
  void WriteUnaryAnswer(const HttpBinding& binding, const grpc::Status& status, std::vector<std::string> responses,
                        bool proto_response, httplib::Response& res);
  // A raw body to a client-streaming method (an import), read chunk by chunk
  // and each chunk sent on as a request as it arrives (streamed_upload.cc).
  void StreamRawUpload(const httplib::Request& req, const HttpBinding& binding, const HttpRequestParts& http,
                       const httplib::ContentReader& reader, uint64_t declared, httplib::Response& res);
  void CallStreaming(const HttpBinding& binding, std::unique_ptr<grpc::ClientContext> context,
                     std::vector<std::string> requests, httplib::Response& res);

  // gRPC-Web (grpc_web.cc): the whole call, its errors in the trailer frame.
  void HandleGrpcWeb(const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& reader);
  void CallGrpcWebStreaming(const google::protobuf::MethodDescriptor& method, bool text,
                            std::unique_ptr<grpc::ClientContext> context, std::string request, httplib::Response& res);

  // WebSocket sessions on a bidi method's REST path (websocket_session.cc).
  void HandleWebSocket(const httplib::Request& req, httplib::Response& res, const RequestPath& path);
  // The session on the upgraded connection (`ssl`: the TLS session or null) until it ends.
  void RunWebSocketSession(int fd, void* ssl, const HttpBinding& binding, const PathBindings& variables,
                           BidiCall& call);

  const google::protobuf::Message& Prototype(const google::protobuf::Descriptor* type) const {
    return *factory_->GetPrototype(type);
  }

  GatewayOptions options_;
  google::protobuf::MessageFactory* factory_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<grpc::GenericStub> stub_;
  CorsPolicy cors_;
  std::vector<HttpBinding> bindings_;
  std::map<std::string, const google::protobuf::MethodDescriptor*> grpc_web_methods_;  // "/pkg.Service/Method"
  std::string openapi_;
  std::atomic<size_t> open_streams_{0};
  CallRegistry calls_;
};

}  // namespace armature::server::gateway
