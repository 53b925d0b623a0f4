// HTTP request ↔ RPC messages for one binding, driven only by the binding
// and the message descriptors:
//  - path variables and query parameters set fields (dotted names reach
//    nested fields, repeated fields repeat the parameter, enums by name);
//  - body "*": the JSON body is the request; body "field": the body is that
//    field; a bytes field with a non-JSON content type takes the raw body;
//    any other body is read as JSON whatever its content type;
//  - a body of Content-Type application/x-protobuf (or application/protobuf)
//    is the whole request message's encoding; path and query still set fields;
//  - client-streaming (and bidi) RPCs get one message per line of an
//    application/x-ndjson body, or one message; a raw bytes body is cut into
//    chunks, the first message carrying the other fields and later ones only
//    the chunk (ImportAsset's contract).
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <google/protobuf/message.h>
#include <grpcpp/grpcpp.h>

#include "server/host/gateway/rest/transcoding/http_rule.h"

namespace armature::server::gateway {

struct HttpRequestParts {
  PathBindings path;                                       // the template's variables
  std::vector<std::pair<std::string, std::string>> query;  // decoded, in order
  // multipart/form-data text fields (multipart_upload.h): set fields as query parameters do.
  std::vector<std::pair<std::string, std::string>> form;
  std::string_view body;
  std::string content_type;  // media type, lower case, no parameters
};

inline constexpr char kProtobufMediaType[] = "application/x-protobuf";
// application/x-protobuf or application/protobuf (media type, lower case).
bool IsProtobufType(const std::string& content_type);
// True when an Accept header lists application/x-protobuf (or
// application/protobuf) with a non-zero quality: the answer is then the
// response message's proto encoding instead of JSON.
bool AcceptsProtobuf(const std::string& accept_header);

// True for the content types whose body is one JSON value per line.
bool IsNdjson(const std::string& content_type);
// True when the body rule names a bytes field and the content type is given
// and not JSON: the raw body is that field. Any other body is read as JSON
// whatever its content type says (curl -d sends form encoding).
bool IsRawBytesBody(const HttpBinding& binding, const std::string& content_type);

// Path variables, query parameters and form fields into `params`.
// INVALID_ARGUMENT naming the parameter.
grpc::Status ParamsMessage(const HttpBinding& binding, const HttpRequestParts& http, google::protobuf::Message* params);

// The serialized request messages. INVALID_ARGUMENT naming the parameter or
// body field on bad input.
grpc::Status TranscodeRequest(const HttpBinding& binding, const google::protobuf::Message& prototype,
                              const HttpRequestParts& http, size_t chunk_bytes, std::vector<std::string>* requests);

// A serialized response as the HTTP body: its JSON, or with response_body
// that field's JSON (raw bytes for a bytes field). RESOURCE_EXHAUSTED, naming
// the limit and the binary encoding's size, once the JSON passes
// `max_json_bytes` (--max-message-mb): the writer stops there.
struct HttpBody {
  std::string content;
  std::string content_type;
};
// `serialized` is freed once parsed, before the JSON is written.
grpc::Status TranscodeResponse(const HttpBinding& binding, const google::protobuf::Message& prototype,
                               std::string serialized, size_t max_json_bytes, HttpBody* out);

}  // namespace armature::server::gateway
