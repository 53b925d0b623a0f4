#include "server/host/gateway/rest/transcoding/http_rule.h"

#include <algorithm>

#include <google/protobuf/descriptor_database.h>

#include "google/api/annotations.pb.h"

namespace armature::server::gateway {
namespace {

namespace pb = google::protobuf;

StatusOr<HttpBinding> Compile(const pb::MethodDescriptor* method, const google::api::HttpRule& rule, int index) {
  HttpBinding b;
  b.method = method;
  b.index = index;
  std::string path;
  switch (rule.pattern_case()) {
    case google::api::HttpRule::kGet: b.http_method = "GET", path = rule.get(); break;
    case google::api::HttpRule::kPut: b.http_method = "PUT", path = rule.put(); break;
    case google::api::HttpRule::kPost: b.http_method = "POST", path = rule.post(); break;
    case google::api::HttpRule::kDelete: b.http_method = "DELETE", path = rule.delete_(); break;
    case google::api::HttpRule::kPatch: b.http_method = "PATCH", path = rule.patch(); break;
    case google::api::HttpRule::kCustom: b.http_method = rule.custom().kind(), path = rule.custom().path(); break;
    default: return Status::InvalidArgument("no HTTP method and path");
  }
  auto compiled = PathTemplate::Parse(path);
  if (!compiled.ok()) return compiled.status();
  b.path = std::move(*compiled);
  for (const std::string& var : b.path.variables()) {
    auto field = ResolveFieldPath(method->input_type(), var);
    if (!field.ok()) return field.status().WithContext("path variable ");
    if (field->back()->is_repeated() || field->back()->type() == pb::FieldDescriptor::TYPE_MESSAGE)
      return Status::InvalidArgument("path variable '" + var + "': must be a singular scalar field");
    b.path_fields.push_back(std::move(*field));
  }
  b.body = rule.body();
  if (!b.body.empty() && b.body != "*") {
    auto field = ResolveFieldPath(method->input_type(), b.body);
    if (!field.ok()) return field.status().WithContext("body ");
    if (field->size() != 1) return Status::InvalidArgument("body '" + b.body + "': must be a top-level field");
    b.body_field = std::move(*field);
  }
  b.response_body = rule.response_body();
  if (!b.response_body.empty()) {
    auto field = ResolveFieldPath(method->output_type(), b.response_body);
    if (!field.ok()) return field.status().WithContext("response_body ");
    if (field->size() != 1)
      return Status::InvalidArgument("response_body '" + b.response_body + "': must be a top-level field");
    b.response_field = std::move(*field);
  }
  return b;
}

}  // namespace

std::string HttpBinding::grpc_method() const { return "/" + method->service()->full_name() + "/" + method->name(); }

StatusOr<std::vector<HttpBinding>> BindingsOf(const pb::MethodDescriptor* method) {
  std::vector<HttpBinding> out;
  if (!method->options().HasExtension(google::api::http)) return out;
  const google::api::HttpRule& rule = method->options().GetExtension(google::api::http);
  std::vector<const google::api::HttpRule*> rules = {&rule};
  for (const auto& extra : rule.additional_bindings()) rules.push_back(&extra);
  for (size_t i = 0; i < rules.size(); ++i) {
    auto b = Compile(method, *rules[i], static_cast<int>(i));
    if (!b.ok())
      return b.status().WithContext(method->full_name() +
                                    (i ? " additional_bindings[" + std::to_string(i - 1) + "]" : "") +
                                    " (google.api.http): ");
    out.push_back(std::move(*b));
  }
  return out;
}

std::vector<const pb::ServiceDescriptor*> GeneratedServicesIn(std::string_view package) {
  std::vector<std::string> files;
  pb::DescriptorPool::internal_generated_database()->FindAllFileNames(&files);
  std::sort(files.begin(), files.end());
  std::vector<const pb::ServiceDescriptor*> services;
  const std::string prefix = std::string(package) + ".";
  for (const auto& name : files) {
    const pb::FileDescriptor* file = pb::DescriptorPool::generated_pool()->FindFileByName(name);
    if (file == nullptr || (file->package() != package && file->package().rfind(prefix, 0) != 0)) continue;
    for (int i = 0; i < file->service_count(); ++i) services.push_back(file->service(i));
  }
  return services;
}

}  // namespace armature::server::gateway
