// The REST bindings of RPCs, read from their (google.api.http) options:
// the main rule and its additional_bindings, each with a compiled path.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <google/protobuf/descriptor.h>

#include "armature/base/status.h"
#include "server/host/gateway/rest/transcoding/field_path.h"
#include "server/host/gateway/rest/transcoding/path_template.h"

namespace armature::server::gateway {

struct HttpBinding {
  const google::protobuf::MethodDescriptor* method = nullptr;
  std::string http_method;  // GET, POST, PUT, PATCH, DELETE or a custom kind
  PathTemplate path;
  std::string body;           // "" (no body), "*" (the whole request) or a field of the request
  FieldPath body_field;       // resolved `body` when it names a field
  std::string response_body;  // "" (the whole response) or a field of the response
  FieldPath response_field;
  std::vector<FieldPath> path_fields;  // the path variables' fields
  int index = 0;                       // 0: the main rule; i: additional_bindings[i-1]

  // "/armature.v1.PoseService/EvaluateClip", what a gRPC channel calls.
  std::string grpc_method() const;
  bool client_streaming() const { return method->client_streaming(); }
  bool server_streaming() const { return method->server_streaming(); }
};

// The bindings of one method; none when it has no (google.api.http) option.
// INVALID_ARGUMENT when a rule is malformed or names a field the messages lack.
StatusOr<std::vector<HttpBinding>> BindingsOf(const google::protobuf::MethodDescriptor* method);

// Every service defined in `package` (or a sub-package) among the files the
// generated pool knows.
std::vector<const google::protobuf::ServiceDescriptor*> GeneratedServicesIn(std::string_view package);

}  // namespace armature::server::gateway
