// proto3 JSON both ways (protobuf's own mapping), with errors that say where:
// malformed JSON gets its line and column, a bad value names its field.
#pragma once

#include <string>
#include <string_view>

#include <google/protobuf/message.h>
#include <grpcpp/grpcpp.h>

namespace armature::server::gateway {

// Parses JSON into `message` (which is cleared first). Either field-name
// spelling is accepted, enums by name (in any case: "world") or number, a bad
// name answered with the allowed ones; unknown fields are an error. `where`
// prefixes messages ("request body: malformed JSON …") and `field_label`
// names a bad field ("request body field 'times[1]': …").
grpc::Status JsonToMessage(std::string_view json, google::protobuf::Message* message, const std::string& where,
                           const std::string& field_label);

// OK when `json` is one JSON value (whitespace around it allowed), else
// INVALID_ARGUMENT "<where>: malformed JSON (byte N): …".
grpc::Status CheckJsonSyntax(std::string_view json, const std::string& where);

// lowerCamelCase names, enums by name, default values printed: the bytes
// protobuf's MessageToJsonString writes with these options, written by
// json/json_writer (fast, one buffer). False, `out` cut short, once the text
// passes `max_bytes`.
bool MessageToJson(const google::protobuf::Message& message, size_t max_bytes, std::string* out);
// The same without a bound, for messages whose size is known to be small.
std::string MessageToJson(const google::protobuf::Message& message);

}  // namespace armature::server::gateway
