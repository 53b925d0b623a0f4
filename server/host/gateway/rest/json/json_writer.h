// A message as JSON, driven by its descriptor and appended to one buffer: the
// text protobuf's MessageToJsonString writes with the gateway's options
// (lowerCamelCase names, every field without presence printed with its
// default, enums by name, 64-bit integers as strings, bytes as base64) — the
// same bytes, at several times the speed and without its tree of nodes
// (about 60 times the answer's size in memory).
//
// Fields in declaration order; a message field, a oneof member or a proto3
// optional only when set; repeated fields and maps always ([] and {}).
#pragma once

#include <cstddef>
#include <string>

#include <google/protobuf/message.h>

namespace armature::server::gateway {

// Appends `message` to `out`. False, `out` holding a cut text, once `out`
// reaches more than `max_bytes`: the writer stops there.
bool AppendMessageJson(const google::protobuf::Message& message, size_t max_bytes, std::string* out);

// Appends the JSON value of one field of `message` (a repeated field as its
// list, an unset message as {}). False past `max_bytes`, as above.
bool AppendFieldJson(const google::protobuf::Message& message, const google::protobuf::FieldDescriptor& field,
                     size_t max_bytes, std::string* out);

}  // namespace armature::server::gateway
