// A form's parts become ImportAsset's chunk messages: read back by the
// server's own ImportUpload (the gRPC side of the protocol), they give the
// main file and every resource byte for byte, whatever the chunk size and
// the order of the parts.
#include <gtest/gtest.h>

#include "armature/v1/assets.pb.h"
#include "server/assets/upload/import_upload.h"
#include "server/host/gateway/rest/multipart_upload.h"

namespace armature::server::gateway {
namespace {

const google::protobuf::MethodDescriptor* Method(const std::string& service, const std::string& method) {
  return v1::ImportAssetRequest::descriptor()->file()->pool()->FindServiceByName(service)->FindMethodByName(method);
}

HttpBinding ImportBinding() {
  auto bindings = BindingsOf(Method("armature.v1.AssetService", "ImportAsset"));
  EXPECT_TRUE(bindings.ok() && bindings->size() == 1);
  return std::move(bindings->front());
}

std::vector<v1::ImportAssetRequest> Parse(const std::vector<std::string>& requests) {
  std::vector<v1::ImportAssetRequest> out(requests.size());
  for (size_t i = 0; i < requests.size(); ++i) EXPECT_TRUE(out[i].ParseFromString(requests[i]));
  return out;
}

TEST(MultipartUpload, OnlyImportAssetTakesAForm) {
  int accepting = 0;
  for (const auto* service : GeneratedServicesIn("armature.v1"))
    for (int i = 0; i < service->method_count(); ++i) {
      auto bindings = BindingsOf(service->method(i));
      ASSERT_TRUE(bindings.ok());
      for (const auto& b : *bindings)
        if (AcceptsMultipartUpload(b)) {
          ++accepting;
          EXPECT_EQ(b.method->full_name(), "armature.v1.AssetService.ImportAsset");
        }
    }
  EXPECT_EQ(accepting, 1);
}

TEST(MultipartUpload, PartsBecomeTheChunkProtocolImportUploadReads) {
  const std::string main = "{\"asset\":1}";  // 11 bytes: chunks of 4, 4, 3
  const std::string a = "0123456789";        // 4, 4, 2
  std::vector<FormPart> form = {{"files", "a.bin", a},
                                {"name", "", "chosen"},
                                {"files", "Scene.GLTF", main},
                                {"files", "tex/b.png", ""},
                                {"replace", "", "true"}};
  HttpRequestParts http;
  http.query = {{"format", "gltf"}};
  std::vector<std::string> requests;
  const auto st = TranscodeMultipartUpload(ImportBinding(), v1::ImportAssetRequest::default_instance(), http,
                                           std::move(form), 4, &requests);
  ASSERT_TRUE(st.ok()) << st.error_message();
  const auto messages = Parse(requests);
  ASSERT_EQ(messages.size(), 7u);
  // The header rides on the first chunk of the main file; each resource starts with its name.
  EXPECT_EQ(messages[0].filename(), "Scene.GLTF");
  EXPECT_EQ(messages[0].name(), "chosen");
  EXPECT_EQ(messages[0].format(), "gltf");
  EXPECT_TRUE(messages[0].replace());
  EXPECT_EQ(messages[0].data(), "{\"as");
  EXPECT_EQ(messages[3].resource(), "a.bin");
  EXPECT_EQ(messages[3].data(), "0123");
  EXPECT_EQ(messages[6].resource(), "tex/b.png");
  EXPECT_EQ(messages[6].data(), "");
  for (size_t i = 1; i < messages.size(); ++i) EXPECT_EQ(messages[i].filename(), "") << i;

  ImportUpload upload(1 << 20);
  for (const auto& m : messages) ASSERT_TRUE(upload.Add(m).ok()) << m.ShortDebugString();
  auto imported = std::move(upload).Finish();
  ASSERT_TRUE(imported.ok());
  EXPECT_EQ(imported->filename, "Scene.GLTF");
  EXPECT_EQ(imported->name, "chosen");
  EXPECT_TRUE(imported->replace);
  EXPECT_EQ(imported->bytes, main);
  ASSERT_EQ(imported->resources.size(), 2u);
  EXPECT_EQ(imported->resources.at("a.bin"), a);
  EXPECT_EQ(imported->resources.at("tex/b.png"), "");
}

TEST(MultipartUpload, AFilenameOrResourceFieldIsRefused) {
  for (const char* field : {"filename", "resource"}) {
    std::vector<FormPart> form = {{"files", "s.gltf", "{}"}, {field, "", "x.bin"}};
    std::vector<std::string> requests;
    const auto st = TranscodeMultipartUpload(ImportBinding(), v1::ImportAssetRequest::default_instance(), {},
                                             std::move(form), 1 << 20, &requests);
    EXPECT_EQ(st.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << field;
    EXPECT_NE(st.error_message().find(std::string("'") + field + "'"), std::string::npos) << st.error_message();
  }
}

}  // namespace
}  // namespace armature::server::gateway
