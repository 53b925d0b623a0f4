// The soak's calls through the HTTP port, each the way a browser or a curl
// user makes it: gRPC-Web (binary frames), binary REST
// (application/x-protobuf) and a WebSocket session in binary frames. Each
// answers a grpc::Status, so the soak tallies them like its gRPC calls.
#pragma once

#include <random>
#include <string>
#include <vector>

#include <google/protobuf/message.h>
#include <grpcpp/grpcpp.h>

namespace armature::soak {

class HttpTransports {
 public:
  explicit HttpTransports(int http_port) : port_(http_port) {}

  // POST /<package.Service>/<Method> as application/grpc-web+proto.
  grpc::Status GrpcWeb(const std::string& method_path, const google::protobuf::Message& request,
                       google::protobuf::Message& response);
  // POST `path` with the request in protobuf, the answer asked for in protobuf.
  grpc::Status RestBinary(const std::string& path, const google::protobuf::Message& request,
                          google::protobuf::Message& response);
  // A session at `path`: each message sent in a binary frame and its answer
  // awaited, then a normal close. A failed session's JSON status frame
  // becomes the status.
  grpc::Status WebSocketSession(const std::string& path, const std::vector<std::string>& messages);

 private:
  int port_;
  std::mt19937 rng_{7};
};

}  // namespace armature::soak
