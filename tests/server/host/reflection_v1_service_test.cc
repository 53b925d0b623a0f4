// Reflection v1 answers, one request at a time, from the generated pool.
#include <algorithm>
#include <set>

#include <gtest/gtest.h>

#include <google/protobuf/descriptor.pb.h>

#include "armature/v1/poses.pb.h"
#include "server/host/reflection_v1_service.h"

namespace armature::server {
namespace {

namespace rv1 = grpc::reflection::v1;

TEST(ReflectionV1, FileContainingSymbolGivesTheFileThenWhatItImports) {
  (void)v1::EvaluateClipRequest::descriptor();  // linked in
  ReflectionV1Service service({"armature.v1.PoseService"});
  rv1::ServerReflectionRequest request;
  request.set_host("h");
  request.set_file_containing_symbol("armature.v1.PoseService.EvaluateClip");
  const auto response = service.Answer(request);
  ASSERT_TRUE(response.has_file_descriptor_response()) << response.ShortDebugString();
  EXPECT_EQ(response.valid_host(), "h");
  EXPECT_EQ(response.original_request().file_containing_symbol(), request.file_containing_symbol());
  std::vector<std::string> names;
  for (const auto& raw : response.file_descriptor_response().file_descriptor_proto()) {
    google::protobuf::FileDescriptorProto file;
    ASSERT_TRUE(file.ParseFromString(raw));
    names.push_back(file.name());
  }
  ASSERT_FALSE(names.empty());
  EXPECT_EQ(names.front(), "armature/v1/poses.proto");
  // Each file once, every import of poses.proto among them.
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  const auto* poses = google::protobuf::DescriptorPool::generated_pool()->FindFileByName("armature/v1/poses.proto");
  for (int i = 0; i < poses->dependency_count(); ++i)
    EXPECT_NE(std::find(names.begin(), names.end(), poses->dependency(i)->name()), names.end())
        << poses->dependency(i)->name();
}

TEST(ReflectionV1, UnknownNamesAndEmptyRequestsAreErrors) {
  ReflectionV1Service service({});
  rv1::ServerReflectionRequest request;
  request.set_file_by_filename("nope.proto");
  auto response = service.Answer(request);
  EXPECT_EQ(response.error_response().error_code(), static_cast<int>(grpc::StatusCode::NOT_FOUND));
  EXPECT_NE(response.error_response().error_message().find("'nope.proto'"), std::string::npos);
  request.mutable_file_containing_extension()->set_containing_type("armature.v1.Nope");
  response = service.Answer(request);
  EXPECT_EQ(response.error_response().error_code(), static_cast<int>(grpc::StatusCode::NOT_FOUND));
  response = service.Answer(rv1::ServerReflectionRequest());
  EXPECT_EQ(response.error_response().error_code(), static_cast<int>(grpc::StatusCode::INVALID_ARGUMENT));
  request.set_list_services("");
  EXPECT_EQ(service.Answer(request).list_services_response().service_size(), 0);
}

}  // namespace
}  // namespace armature::server
