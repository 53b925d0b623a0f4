// The transcoder on the API's own bindings: what a body bound to one field
// may set. Found by server_transcode_fuzz (tests/fuzz/regressions/).
#include <gtest/gtest.h>

#include "armature/v1/assets.pb.h"
#include "server/host/gateway/rest/transcoding/transcoder.h"

namespace armature::server::gateway {
namespace {

HttpBinding ImportBinding() {
  auto bindings = BindingsOf(
      v1::ImportAssetRequest::descriptor()->file()->FindServiceByName("AssetService")->FindMethodByName("ImportAsset"));
  EXPECT_TRUE(bindings.ok() && bindings->size() == 1);
  return std::move(bindings->front());
}

HttpRequestParts Import(std::string_view body, const std::string& content_type) {
  HttpRequestParts http;
  http.query = {{"filename", "walk.bvh"}};
  http.body = body;
  http.content_type = content_type;
  return http;
}

// Before, the body was pasted into {"data": <body>}: '"AAAA","name":"x"'
// came out as {"data":"AAAA","name":"x"} and set the name from the body.
TEST(Transcoder, ABodyBoundToAFieldIsOneJsonValue) {
  const HttpBinding binding = ImportBinding();
  std::vector<std::string> requests;
  const auto st = TranscodeRequest(binding, v1::ImportAssetRequest::default_instance(),
                                   Import(R"("AAAA","name":"x")", "application/json"), 1 << 20, &requests);
  EXPECT_EQ(st.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(st.error_message().rfind("request body: malformed JSON (byte 7): ", 0), 0u) << st.error_message();

  const auto line =
      TranscodeRequest(binding, v1::ImportAssetRequest::default_instance(),
                       Import("\"AAAA\"\n\"AAAA\",\"resource\":\"r\"\n", "application/x-ndjson"), 1 << 20, &requests);
  EXPECT_EQ(line.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(line.error_message().rfind("request body line 2: malformed JSON (byte 7): ", 0), 0u)
      << line.error_message();
}

TEST(Transcoder, ABodyBoundToAFieldSetsThatFieldAndThePathAndQueryTheRest) {
  std::vector<std::string> requests;
  const auto st = TranscodeRequest(ImportBinding(), v1::ImportAssetRequest::default_instance(),
                                   Import(" \"SElF\" ", "application/json"), 1 << 20, &requests);
  ASSERT_TRUE(st.ok()) << st.error_message();
  ASSERT_EQ(requests.size(), 1u);
  v1::ImportAssetRequest m;
  ASSERT_TRUE(m.ParseFromString(requests[0]));
  EXPECT_EQ(m.data(), "HIE");
  EXPECT_EQ(m.filename(), "walk.bvh");
  EXPECT_EQ(m.name(), "");
  EXPECT_EQ(m.resource(), "");
}

// Binary REST: an application/x-protobuf body is the whole request message,
// not the raw bytes of the body field; the query still sets its fields.
TEST(Transcoder, AProtobufBodyIsTheWholeRequestMessage) {
  v1::ImportAssetRequest sent;
  sent.set_name("walker");
  sent.set_data(std::string("\x00\x01\xff", 3));
  sent.set_filename("from-body.bvh");
  const std::string encoded = sent.SerializeAsString();
  std::vector<std::string> requests;
  const auto st = TranscodeRequest(ImportBinding(), v1::ImportAssetRequest::default_instance(),
                                   Import(encoded, "application/x-protobuf"), 1 << 20, &requests);
  ASSERT_TRUE(st.ok()) << st.error_message();
  ASSERT_EQ(requests.size(), 1u);
  v1::ImportAssetRequest m;
  ASSERT_TRUE(m.ParseFromString(requests[0]));
  EXPECT_EQ(m.name(), "walker");
  EXPECT_EQ(m.data(), std::string("\x00\x01\xff", 3));
  EXPECT_EQ(m.filename(), "walk.bvh");  // the query wins

  const auto bad = TranscodeRequest(ImportBinding(), v1::ImportAssetRequest::default_instance(),
                                    Import("\xff\xff\xff", "application/protobuf"), 1 << 20, &requests);
  EXPECT_EQ(bad.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(bad.error_message(),
            "request body: not a valid armature.v1.ImportAssetRequest encoding (Content-Type application/protobuf)");
  EXPECT_FALSE(IsRawBytesBody(ImportBinding(), "application/x-protobuf"));
  EXPECT_TRUE(IsRawBytesBody(ImportBinding(), "application/octet-stream"));
}

TEST(Transcoder, AcceptHeadersAskingForProtobuf) {
  EXPECT_TRUE(AcceptsProtobuf("application/x-protobuf"));
  EXPECT_TRUE(AcceptsProtobuf("application/json;q=0.5, Application/X-Protobuf"));
  EXPECT_TRUE(AcceptsProtobuf("application/protobuf; q=0.9"));
  EXPECT_FALSE(AcceptsProtobuf(""));
  EXPECT_FALSE(AcceptsProtobuf("*/*"));
  EXPECT_FALSE(AcceptsProtobuf("application/json"));
  EXPECT_FALSE(AcceptsProtobuf("application/x-protobuf;q=0"));
  EXPECT_FALSE(AcceptsProtobuf("application/x-protobuf; q=0.0, application/json"));
  EXPECT_FALSE(AcceptsProtobuf("application/x-protobuffer"));
}

}  // namespace
}  // namespace armature::server::gateway
