// A dotted path to a field of a request message ("pose.rotations"), as path
// templates and query parameters name it: proto names or JSON names.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <google/protobuf/descriptor.h>

#include "armature/base/status.h"

namespace armature::server::gateway {

using FieldPath = std::vector<const google::protobuf::FieldDescriptor*>;

// Every step but the last must be a singular message field.
StatusOr<FieldPath> ResolveFieldPath(const google::protobuf::Descriptor* message, std::string_view dotted);

// "pose.rotations" with proto names, whatever spelling resolved it.
std::string ProtoNameOf(const FieldPath& path);

}  // namespace armature::server::gateway
