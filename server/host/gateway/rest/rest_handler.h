// REST/JSON on the API's paths: one generic transcoder over every RPC that
// carries a (google.api.http) rule. A request is matched against the route
// table, its token checked before its body is read, its path, query and
// (bounded) body turned into request messages (transcoding/transcoder.h) and
// the call made through the call factory; the answer goes back as JSON (or
// protobuf), response streams as Server-Sent Events (sse.h), uploads as they
// arrive (streamed_upload.cc, multipart_upload.h). A new annotated RPC needs
// no code here.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <grpcpp/grpcpp.h>

#include "server/host/gateway/common/call_factory.h"
#include "server/host/gateway/rest/route_table.h"
#include "server/host/gateway/rest/transcoding/transcoder.h"

namespace httplib {
struct Request;
struct Response;
class ContentReader;
}  // namespace httplib

namespace armature::server::gateway {

class RestHandler {
 public:
  // Both outlive the handler.
  RestHandler(const RouteTable& routes, CallFactory& calls) : routes_(routes), calls_(calls) {}

  // A request on `path` (`reader`: its body unread, or null when httplib read it).
  void Handle(const httplib::Request& req, httplib::Response& res, const RequestPath& path,
              const httplib::ContentReader* reader);

 private:
  size_t BodyLimit(const HttpBinding& binding, const std::string& content_type) const;
  // A multipart/form-data upload into `requests` (multipart_upload.h); false
  // once it has written the error.
  bool ReadMultipartUpload(const HttpBinding& binding, const httplib::ContentReader* reader, uint64_t declared,
                           const HttpRequestParts& http, httplib::Response& res, std::vector<std::string>* requests);
  // Sends `requests` to the binding's method and writes its answer.
  void Dispatch(const httplib::Request& req, const HttpBinding& binding, std::vector<std::string> requests,
                httplib::Response& res);
  // Writes a unary or client-streaming call's answer: its one response as
  // JSON (or protobuf), or its error.
  void WriteUnaryAnswer(const HttpBinding& binding, const grpc::Status& status, std::vector<std::string> responses,
                        bool proto_response, httplib::Response& res);
  // A raw body to a client-streaming method (an import), read chunk by chunk
  // and each chunk sent on as a request as it arrives (streamed_upload.cc).
  void StreamRawUpload(const httplib::Request& req, const HttpBinding& binding, const HttpRequestParts& http,
                       const httplib::ContentReader& reader, uint64_t declared, httplib::Response& res);
  // A response stream as Server-Sent Events.
  void CallStreaming(const HttpBinding& binding, std::unique_ptr<grpc::ClientContext> context,
                     std::vector<std::string> requests, httplib::Response& res);

  const RouteTable& routes_;
  CallFactory& calls_;
};

}  // namespace armature::server::gateway
