// gRPC-Web on the HTTP port (Envoy's grpc-web filter, without the proxy):
// POST /armature.v1.<Service>/<Method> with Content-Type application/grpc-web
// (+proto) or application/grpc-web-text. The request frame's bytes are the
// request message, forwarded untouched through the call factory. Every
// answer is HTTP 200 with the status in a trailer frame at the end of the
// body; server streams write each message as a frame when it arrives (chunked).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <google/protobuf/descriptor.h>
#include <grpcpp/grpcpp.h>

#include "server/host/gateway/common/call_factory.h"

namespace httplib {
struct Request;
struct Response;
class ContentReader;
}  // namespace httplib

namespace armature::server::gateway {

class GrpcWebHandler {
 public:
  // Every method of `services`; `calls` outlives the handler.
  GrpcWebHandler(const std::vector<const google::protobuf::ServiceDescriptor*>& services, CallFactory& calls);

  // True for "/pkg.Service/Method" of a served method.
  bool Serves(const std::string& path) const { return methods_.count(path) > 0; }
  // The whole call, its errors in the trailer frame.
  void Handle(const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& reader);

 private:
  // The request's one message from its body (bounded, base64 in text mode).
  grpc::Status ReadRequestMessage(const httplib::ContentReader& reader, bool text,
                                  const google::protobuf::MethodDescriptor& method, httplib::Response& res,
                                  std::string* message) const;
  void CallUnary(const google::protobuf::MethodDescriptor& method, bool text,
                 std::unique_ptr<grpc::ClientContext> context, std::string request, httplib::Response& res);
  void CallStreaming(const google::protobuf::MethodDescriptor& method, bool text,
                     std::unique_ptr<grpc::ClientContext> context, std::string request, httplib::Response& res);

  std::map<std::string, const google::protobuf::MethodDescriptor*> methods_;  // "/pkg.Service/Method"
  CallFactory& calls_;
};

}  // namespace armature::server::gateway
