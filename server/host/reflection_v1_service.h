// grpc.reflection.v1.ServerReflection, beside the v1alpha service gRPC's
// plugin provides (Debian's grpc++ 1.51 ships only v1alpha; newer clients
// such as grpcurl ask v1 first). Answers from the generated descriptor pool,
// as the v1alpha plugin does; like it, served without the auth gate.
#pragma once

#include <string>
#include <vector>

#include <google/protobuf/descriptor.h>
#include <grpcpp/grpcpp.h>

#include "grpc/reflection/v1/reflection.grpc.pb.h"

namespace armature::server {

class ReflectionV1Service final : public grpc::reflection::v1::ServerReflection::Service {
 public:
  // `services`: the full names list_services answers, e.g. "armature.v1.PoseService".
  explicit ReflectionV1Service(std::vector<std::string> services);

  grpc::Status ServerReflectionInfo(
      grpc::ServerContext* context,
      grpc::ServerReaderWriter<grpc::reflection::v1::ServerReflectionResponse,
                               grpc::reflection::v1::ServerReflectionRequest>* stream) override;

  // One request's answer: a file_descriptor_response, the extension numbers,
  // the service list, or an error_response (NOT_FOUND naming what was asked).
  grpc::reflection::v1::ServerReflectionResponse Answer(
      const grpc::reflection::v1::ServerReflectionRequest& request) const;

 private:
  grpc::Status FileByName(const std::string& name, grpc::reflection::v1::ServerReflectionResponse* response) const;
  grpc::Status FileContainingSymbol(const std::string& symbol,
                                    grpc::reflection::v1::ServerReflectionResponse* response) const;
  grpc::Status FileContainingExtension(const grpc::reflection::v1::ExtensionRequest& request,
                                       grpc::reflection::v1::ServerReflectionResponse* response) const;
  grpc::Status AllExtensionNumbers(const std::string& type,
                                   grpc::reflection::v1::ServerReflectionResponse* response) const;

  const google::protobuf::DescriptorPool* pool_;
  std::vector<std::string> services_;
};

}  // namespace armature::server
