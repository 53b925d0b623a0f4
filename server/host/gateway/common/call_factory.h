// The layer every protocol of the gateway (REST, gRPC-Web, WebSocket) makes
// its calls through: the server's own gRPC services over the in-process
// channel, so the auth gate, validation, limits and metrics of gRPC apply to
// all of them. It checks the token early (before a body is read), builds each
// call's context (deadline, forwarded headers, the client's address), hands
// out the message prototypes, counts response streams and sessions against
// --max-streams and registers every call for the drain at shutdown.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>

#include "server/host/gateway/common/bidi_call.h"
#include "server/host/gateway/common/call_registry.h"
#include "server/host/gateway/common/gateway_options.h"
#include "server/host/gateway/common/generic_call.h"

namespace httplib {
struct Request;
}

namespace armature::server::gateway {

class CallFactory {
 public:
  // `factory` makes the request and response messages (generated or dynamic).
  CallFactory(GatewayOptions options, google::protobuf::MessageFactory* factory,
              std::shared_ptr<grpc::Channel> channel);

  const GatewayOptions& options() const { return options_; }
  const google::protobuf::Message& Prototype(const google::protobuf::Descriptor* type) const {
    return *factory_->GetPrototype(type);
  }
  CallRegistry& calls() { return calls_; }

  // OK without --auth-token-file or for a token it lists, else UNAUTHENTICATED.
  grpc::Status Authenticate(const std::string& authorization) const;
  // The context of a call made for `req`: the deadline (`grpc-timeout`, else
  // the default unless it streams responses), the forwarded headers and the
  // client's address. INVALID_ARGUMENT naming a malformed header.
  grpc::Status MakeContext(const httplib::Request& req, bool server_streaming,
                           std::unique_ptr<grpc::ClientContext>* context) const;

  // A call with all its requests, run to its end: its responses and status
  // (UNAVAILABLE once draining).
  grpc::Status CallWhole(const std::string& method, std::unique_ptr<grpc::ClientContext> context,
                         std::vector<std::string> requests, std::vector<std::string>* responses);
  // A client-streaming call whose requests follow (an upload read as it
  // arrives), registered; UNAVAILABLE once draining. End it with EndUpload.
  grpc::Status StartUpload(const std::string& method, std::unique_ptr<grpc::ClientContext> context,
                           std::unique_ptr<GenericCall>* call);
  void EndUpload(GenericCall* call) { calls_.Remove(call); }
  // A response stream (SSE, gRPC-Web): one of the --max-streams slots, then
  // the call, registered. RESOURCE_EXHAUSTED when no slot is free (nothing
  // started), UNAVAILABLE once draining (`call` cancels as it goes). End it
  // with EndStream.
  grpc::Status StartStream(const std::string& method, std::unique_ptr<grpc::ClientContext> context,
                           std::vector<std::string> requests, std::shared_ptr<GenericCall>* call);
  void EndStream(GenericCall* call) { ReleaseSlot(call); }
  // A WebSocket session's bidi call, likewise (its slot named a session).
  grpc::Status StartSession(const std::string& method, std::unique_ptr<grpc::ClientContext> context,
                            std::unique_ptr<BidiCall>* call);
  void EndSession(BidiCall* call) { ReleaseSlot(call); }

 private:
  // A slot of --max-streams; RESOURCE_EXHAUSTED "too many open <what>" when none is free.
  grpc::Status TakeStreamSlot(const std::string& what);
  // A call started in a slot, registered; once draining, the slot freed
  // and UNAVAILABLE.
  template <typename CallPtr>
  grpc::Status RegisterInSlot(const CallPtr& call) {
    if (calls_.Add(call.get())) return grpc::Status::OK;
    --open_streams_;
    return ShuttingDown();
  }
  template <typename Call>
  void ReleaseSlot(Call* call) {
    calls_.Remove(call);
    --open_streams_;
  }

  GatewayOptions options_;
  google::protobuf::MessageFactory* factory_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<grpc::GenericStub> stub_;
  std::atomic<size_t> open_streams_{0};
  CallRegistry calls_;
};

}  // namespace armature::server::gateway
