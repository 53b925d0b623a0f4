#include "server/host/auth/auth_gate.h"

#include <deque>

#include <google/protobuf/descriptor.h>
#include <grpcpp/impl/codegen/server_callback_handlers.h>
#include <grpcpp/impl/rpc_service_method.h>
#include <grpcpp/impl/service_type.h>

#include "server/rpc/caller_identity.h"
#include "server/rpc/grpc_status.h"

namespace armature::server {
namespace {

using grpc::ByteBuffer;
using grpc::internal::MethodHandler;
using grpc::internal::RpcMethod;

Status Rejection(const BearerTokens& tokens, const grpc::ServerContextBase& context) {
  const Status st = tokens.Check(AuthorizationOf(context));
  // A call only reaches a rejecting handler when the check failed; keep the
  // code right even if the metadata were to change in between.
  return st.ok() ? Status(StatusCode::kUnauthenticated, "unauthenticated") : st;
}

// Reactors that finish at once, never reading the request.
template <class Base>
class Rejected final : public Base {
 public:
  explicit Rejected(const Status& status) { this->Finish(ToGrpcStatus(status)); }
  void OnDone() override { delete this; }
};

// A handler of the right streaming kind that only finishes the call with
// the reason it was refused. Its messages are raw bytes, never parsed.
std::unique_ptr<MethodHandler> MakeRejectingHandler(RpcMethod::RpcType type,
                                                    std::shared_ptr<const BearerTokens> tokens) {
  namespace gi = grpc::internal;
  switch (type) {
    case RpcMethod::NORMAL_RPC:
      return std::make_unique<gi::CallbackUnaryHandler<ByteBuffer, ByteBuffer>>(
          [tokens](grpc::CallbackServerContext* context, const ByteBuffer*, ByteBuffer*) {
            return FinishUnary(context, Rejection(*tokens, *context));
          });
    case RpcMethod::CLIENT_STREAMING:
      return std::make_unique<gi::CallbackClientStreamingHandler<ByteBuffer, ByteBuffer>>(
          [tokens](grpc::CallbackServerContext* context, ByteBuffer*) {
            return new Rejected<grpc::ServerReadReactor<ByteBuffer>>(Rejection(*tokens, *context));
          });
    case RpcMethod::SERVER_STREAMING:
      return std::make_unique<gi::CallbackServerStreamingHandler<ByteBuffer, ByteBuffer>>(
          [tokens](grpc::CallbackServerContext* context, const ByteBuffer*) {
            return new Rejected<grpc::ServerWriteReactor<ByteBuffer>>(Rejection(*tokens, *context));
          });
    case RpcMethod::BIDI_STREAMING:
      return std::make_unique<gi::CallbackBidiHandler<ByteBuffer, ByteBuffer>>(
          [tokens](grpc::CallbackServerContext* context) {
            return new Rejected<grpc::ServerBidiReactor<ByteBuffer, ByteBuffer>>(Rejection(*tokens, *context));
          });
  }
  return nullptr;
}

// Decides per call. The request bytes are kept unparsed until then, so
// they are parsed (and later freed) by whichever handler takes the call.
class GateHandler final : public MethodHandler {
 public:
  GateHandler(MethodHandler* inner, RpcMethod::RpcType type, std::shared_ptr<const BearerTokens> tokens)
      : inner_(inner),
        rejecting_(MakeRejectingHandler(type, tokens)),
        tokens_(std::move(tokens)),
        has_request_payload_(type == RpcMethod::NORMAL_RPC || type == RpcMethod::SERVER_STREAMING) {}

  void* Deserialize(grpc_call*, grpc_byte_buffer* request, grpc::Status* status, void** handler_data) override {
    *status = grpc::Status::OK;
    *handler_data = nullptr;
    return request;
  }

  void RunHandler(const HandlerParameter& param) override {
    const bool allowed = tokens_->Check(AuthorizationOf(*param.server_context)).ok();
    MethodHandler* target = allowed ? inner_ : rejecting_.get();
    void* request = nullptr;
    void* handler_data = nullptr;
    grpc::Status status = param.status;
    if (has_request_payload_)
      request = target->Deserialize(param.call->call(), static_cast<grpc_byte_buffer*>(param.request), &status,
                                    &handler_data);
    target->RunHandler(
        HandlerParameter(param.call, param.server_context, request, status, handler_data, param.call_requester));
  }

 private:
  MethodHandler* inner_;  // owned by the wrapped service
  std::unique_ptr<MethodHandler> rejecting_;
  std::shared_ptr<const BearerTokens> tokens_;
  bool has_request_payload_;
};

class GatedService final : public grpc::Service {
 public:
  GatedService(std::unique_ptr<grpc::Service> inner, const google::protobuf::ServiceDescriptor& service,
               std::shared_ptr<const BearerTokens> tokens)
      : inner_(std::move(inner)) {
    for (int i = 0; i < service.method_count(); ++i) {
      const google::protobuf::MethodDescriptor& m = *service.method(i);
      const RpcMethod::RpcType type =
          m.client_streaming() ? (m.server_streaming() ? RpcMethod::BIDI_STREAMING : RpcMethod::CLIENT_STREAMING)
                               : (m.server_streaming() ? RpcMethod::SERVER_STREAMING : RpcMethod::NORMAL_RPC);
      // gRPC's generated services add their methods in the .proto's order.
      const std::string& path = paths_.emplace_back("/" + service.full_name() + "/" + m.name());
      AddMethod(new grpc::internal::RpcServiceMethod(path.c_str(), type, nullptr));
      MarkMethodCallback(i, new GateHandler(HandlerOf(*inner_, i), type, tokens));
    }
  }

 private:
  // The protected accessor of another Service, through a member pointer
  // named via this derived class.
  static MethodHandler* HandlerOf(grpc::Service& service, int index) {
    return (service.*&GatedService::GetHandler)(index);
  }

  std::unique_ptr<grpc::Service> inner_;
  std::deque<std::string> paths_;  // stable storage for the method names gRPC keeps pointers to
};

}  // namespace

StatusOr<std::unique_ptr<grpc::Service>> GateService(std::unique_ptr<grpc::Service> inner, const std::string& full_name,
                                                     std::shared_ptr<const BearerTokens> tokens) {
  const auto* descriptor = google::protobuf::DescriptorPool::generated_pool()->FindServiceByName(full_name);
  if (descriptor == nullptr) return Status::InvalidArgument("auth gate: unknown service '" + full_name + "'");
  if (inner->has_synchronous_methods() || inner->has_async_methods() || inner->has_generic_methods())
    return Status::InvalidArgument("auth gate: service '" + full_name + "' must use only callback methods");
  return std::unique_ptr<grpc::Service>(new GatedService(std::move(inner), *descriptor, std::move(tokens)));
}

}  // namespace armature::server
