#include "server/host/reflection_v1_service.h"

#include <unordered_set>

#include <google/protobuf/descriptor.pb.h>

#include "armature/base/utf8.h"

namespace armature::server {
namespace {

namespace pb = google::protobuf;
namespace rv1 = grpc::reflection::v1;

grpc::Status NotFound(const std::string& what, const std::string& name) {
  return grpc::Status(grpc::StatusCode::NOT_FOUND,
                      what + " '" + EscapeForMessage(name, 256) + "' is not known to this server");
}

// `file` and, once each, every file it imports, directly or not: a client
// can build the descriptors from one answer.
void AddFileAndDependencies(const pb::FileDescriptor* file, std::unordered_set<std::string>* seen,
                            rv1::FileDescriptorResponse* out) {
  if (!seen->insert(file->name()).second) return;
  pb::FileDescriptorProto proto;
  file->CopyTo(&proto);
  out->add_file_descriptor_proto(proto.SerializeAsString());
  for (int i = 0; i < file->dependency_count(); ++i) AddFileAndDependencies(file->dependency(i), seen, out);
}

void AddFile(const pb::FileDescriptor* file, rv1::ServerReflectionResponse* response) {
  std::unordered_set<std::string> seen;
  AddFileAndDependencies(file, &seen, response->mutable_file_descriptor_response());
}

}  // namespace

ReflectionV1Service::ReflectionV1Service(std::vector<std::string> services)
    : pool_(pb::DescriptorPool::generated_pool()), services_(std::move(services)) {}

grpc::Status ReflectionV1Service::ServerReflectionInfo(
    grpc::ServerContext*,
    grpc::ServerReaderWriter<rv1::ServerReflectionResponse, rv1::ServerReflectionRequest>* stream) {
  rv1::ServerReflectionRequest request;
  while (stream->Read(&request))
    if (!stream->Write(Answer(request))) break;
  return grpc::Status::OK;
}

rv1::ServerReflectionResponse ReflectionV1Service::Answer(const rv1::ServerReflectionRequest& request) const {
  rv1::ServerReflectionResponse response;
  grpc::Status status;
  switch (request.message_request_case()) {
    case rv1::ServerReflectionRequest::kFileByFilename:
      status = FileByName(request.file_by_filename(), &response);
      break;
    case rv1::ServerReflectionRequest::kFileContainingSymbol:
      status = FileContainingSymbol(request.file_containing_symbol(), &response);
      break;
    case rv1::ServerReflectionRequest::kFileContainingExtension:
      status = FileContainingExtension(request.file_containing_extension(), &response);
      break;
    case rv1::ServerReflectionRequest::kAllExtensionNumbersOfType:
      status = AllExtensionNumbers(request.all_extension_numbers_of_type(), &response);
      break;
    case rv1::ServerReflectionRequest::kListServices:
      for (const std::string& name : services_)
        response.mutable_list_services_response()->add_service()->set_name(name);
      break;
    case rv1::ServerReflectionRequest::MESSAGE_REQUEST_NOT_SET:
      status = grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                            "message_request: set one of file_by_filename, file_containing_symbol, "
                            "file_containing_extension, all_extension_numbers_of_type or list_services");
      break;
  }
  if (!status.ok()) {
    response.mutable_error_response()->set_error_code(static_cast<int32_t>(status.error_code()));
    response.mutable_error_response()->set_error_message(status.error_message());
  }
  response.set_valid_host(request.host());
  *response.mutable_original_request() = request;
  return response;
}

grpc::Status ReflectionV1Service::FileByName(const std::string& name, rv1::ServerReflectionResponse* response) const {
  const pb::FileDescriptor* file = pool_->FindFileByName(name);
  if (!file) return NotFound("file", name);
  AddFile(file, response);
  return grpc::Status::OK;
}

grpc::Status ReflectionV1Service::FileContainingSymbol(const std::string& symbol,
                                                       rv1::ServerReflectionResponse* response) const {
  const pb::FileDescriptor* file = pool_->FindFileContainingSymbol(symbol);
  if (!file) return NotFound("symbol", symbol);
  AddFile(file, response);
  return grpc::Status::OK;
}

grpc::Status ReflectionV1Service::FileContainingExtension(const rv1::ExtensionRequest& request,
                                                          rv1::ServerReflectionResponse* response) const {
  const pb::Descriptor* type = pool_->FindMessageTypeByName(request.containing_type());
  if (!type) return NotFound("message type", request.containing_type());
  const pb::FieldDescriptor* extension = pool_->FindExtensionByNumber(type, request.extension_number());
  if (!extension)
    return NotFound("extension number " + std::to_string(request.extension_number()) + " of",
                    request.containing_type());
  AddFile(extension->file(), response);
  return grpc::Status::OK;
}

grpc::Status ReflectionV1Service::AllExtensionNumbers(const std::string& type_name,
                                                      rv1::ServerReflectionResponse* response) const {
  const pb::Descriptor* type = pool_->FindMessageTypeByName(type_name);
  if (!type) return NotFound("message type", type_name);
  std::vector<const pb::FieldDescriptor*> extensions;
  pool_->FindAllExtensions(type, &extensions);
  auto* out = response->mutable_all_extension_numbers_response();
  out->set_base_type_name(type->full_name());
  for (const auto* extension : extensions) out->add_extension_number(extension->number());
  return grpc::Status::OK;
}

}  // namespace armature::server
