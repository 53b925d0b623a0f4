#include "server/host/gateway/rest/transcoding/field_path.h"

namespace armature::server::gateway {

StatusOr<FieldPath> ResolveFieldPath(const google::protobuf::Descriptor* message, std::string_view dotted) {
  FieldPath path;
  std::string where = "'";  // built stepwise: GCC 12 warns falsely on "'" + std::string(...)
  where.append(dotted).append("': ");
  const google::protobuf::Descriptor* current = message;
  size_t start = 0;
  while (true) {
    const size_t dot = dotted.find('.', start);
    const std::string name(dotted.substr(start, dot == std::string_view::npos ? std::string_view::npos : dot - start));
    if (current == nullptr)
      return Status::InvalidArgument(where + "'" + path.back()->name() + "' is not a message, so it has no field '" +
                                     name + "'");
    const google::protobuf::FieldDescriptor* field = current->FindFieldByName(name);
    if (field == nullptr) field = current->FindFieldByCamelcaseName(name);
    for (int i = 0; field == nullptr && i < current->field_count(); ++i)
      if (current->field(i)->json_name() == name) field = current->field(i);
    if (field == nullptr) return Status::InvalidArgument(where + current->name() + " has no field '" + name + "'");
    path.push_back(field);
    if (dot == std::string_view::npos) break;
    if (field->is_repeated())
      return Status::InvalidArgument(where + "'" + field->name() +
                                     "' is repeated, so its fields cannot be set one by one");
    current = field->message_type();
    start = dot + 1;
  }
  return path;
}

std::string ProtoNameOf(const FieldPath& path) {
  std::string out;
  for (const auto* f : path) out += (out.empty() ? "" : ".") + f->name();
  return out;
}

}  // namespace armature::server::gateway
