// gRPC-Web framing against bytes written out by hand from the protocol text
// (PROTOCOL-WEB.md: flag byte, 4-byte big-endian length; trailers as HTTP/1
// header lines) and base64 against RFC 4648's test vectors.
#include <gtest/gtest.h>

#include "server/host/gateway/grpc_web/grpc_web_framing.h"

namespace armature::server::gateway {
namespace {

using namespace std::string_literals;

TEST(GrpcWebFraming, ADataFrameIsFlagLengthAndPayload) {
  std::string out;
  AppendGrpcWebFrame(kGrpcWebDataFlag, "abc", &out);
  EXPECT_EQ(out, "\x00\x00\x00\x00\x03"s + "abc");
  out.clear();
  AppendGrpcWebFrame(kGrpcWebDataFlag, std::string(0x010203, 'x'), &out);
  ASSERT_EQ(out.size(), 5u + 0x010203);
  EXPECT_EQ(out.substr(0, 5), "\x00\x00\x01\x02\x03"s);
  out.clear();
  AppendGrpcWebFrame(kGrpcWebDataFlag, "", &out);  // an empty message is a frame too
  EXPECT_EQ(out, "\x00\x00\x00\x00\x00"s);
}

TEST(GrpcWebFraming, TheTrailerFrameCarriesStatusAndPercentEncodedMessage) {
  const std::string ok = GrpcWebTrailerFrame(grpc::Status::OK);
  const std::string ok_text = "grpc-status: 0\r\ngrpc-message: \r\n";
  EXPECT_EQ(ok, "\x80\x00\x00\x00"s + static_cast<char>(ok_text.size()) + ok_text);

  const std::string frame =
      GrpcWebTrailerFrame(grpc::Status(grpc::StatusCode::NOT_FOUND, "clip 'wälk' not found: 100%\n"));
  const std::string text = "grpc-status: 5\r\ngrpc-message: clip 'w%C3%A4lk' not found: 100%25%0A\r\n";
  EXPECT_EQ(frame, "\x80\x00\x00\x00"s + static_cast<char>(text.size()) + text);
}

TEST(GrpcWebFraming, PercentEncodingRoundTripsAndKeepsLoneSigns) {
  EXPECT_EQ(PercentEncode("a b~"), "a b~");
  EXPECT_EQ(PercentEncode("\x7f\x01%"), "%7F%01%25");
  EXPECT_EQ(PercentDecode("clip 'w%C3%A4lk' 100%25"), "clip 'wälk' 100%");
  EXPECT_EQ(PercentDecode("50% off %zz %4"), "50% off %zz %4");
  const std::string all = [] {
    std::string s;
    for (int c = 0; c < 256; ++c) s += static_cast<char>(c);
    return s;
  }();
  EXPECT_EQ(PercentDecode(PercentEncode(all)), all);
}

TEST(GrpcWebFraming, RequestFramesAreSplitInOrder) {
  const std::string body = "\x00\x00\x00\x00\x02"s + "hi" + "\x00\x00\x00\x00\x00"s + "\x00\x00\x00\x00\x01"s + "!";
  std::vector<std::string> messages;
  ASSERT_TRUE(ParseGrpcWebFrames(body, 100, &messages).ok());
  EXPECT_EQ(messages, (std::vector<std::string>{"hi", "", "!"}));
  ASSERT_TRUE(ParseGrpcWebFrames("", 100, &messages).ok());
  EXPECT_TRUE(messages.empty());
}

TEST(GrpcWebFraming, MalformedRequestFramesAreRefusedWithTheirReason) {
  std::vector<std::string> messages;
  auto expect = [&](const std::string& body, grpc::StatusCode code, const std::string& fragment) {
    const grpc::Status st = ParseGrpcWebFrames(body, 1000, &messages);
    EXPECT_EQ(st.error_code(), code) << st.error_message();
    EXPECT_NE(st.error_message().find(fragment), std::string::npos) << st.error_message();
  };
  expect("\x00\x00\x00"s, grpc::StatusCode::INVALID_ARGUMENT, "3 bytes are too few for the 5-byte header");
  expect("\x00\x00\x00\x00\x05"s + "abc", grpc::StatusCode::INVALID_ARGUMENT,
         "its length prefix says 5 bytes but only 3 follow");
  // A huge length prefix is refused before anything is allocated for it.
  expect("\x00\xff\xff\xff\xff"s + "abc", grpc::StatusCode::RESOURCE_EXHAUSTED,
         "its length 4294967295 exceeds the limit of 1000 bytes");
  expect("\x01\x00\x00\x00\x01"s + "a", grpc::StatusCode::UNIMPLEMENTED, "compressed messages are not supported");
  expect("\x80\x00\x00\x00\x00"s, grpc::StatusCode::INVALID_ARGUMENT, "a trailer frame (flag 0x80) in a request");
  expect("\x02\x00\x00\x00\x00"s, grpc::StatusCode::INVALID_ARGUMENT, "unknown flag byte 2");
  // The second frame is named by its number and offset.
  expect("\x00\x00\x00\x00\x01"s + "a" + "\x00\x00"s, grpc::StatusCode::INVALID_ARGUMENT,
         "gRPC-Web frame 2 at byte 6: 2 bytes are too few");
}

TEST(GrpcWebFraming, Base64MatchesRfc4648Vectors) {
  const std::pair<const char*, const char*> vectors[] = {{"", ""},
                                                         {"f", "Zg=="},
                                                         {"fo", "Zm8="},
                                                         {"foo", "Zm9v"},
                                                         {"foob", "Zm9vYg=="},
                                                         {"fooba", "Zm9vYmE="},
                                                         {"foobar", "Zm9vYmFy"}};
  for (const auto& [plain, encoded] : vectors) {
    EXPECT_EQ(Base64Encode(plain), encoded);
    std::string decoded;
    ASSERT_TRUE(Base64Decode(encoded, &decoded)) << encoded;
    EXPECT_EQ(decoded, plain);
  }
  EXPECT_EQ(Base64Encode("\xff\xfe\x00"s), "//4A");
}

TEST(GrpcWebFraming, Base64TakesConcatenatedPaddedChunksAndRefusesGarbage) {
  std::string decoded;
  ASSERT_TRUE(Base64Decode("Zg==Zm8=Zm9v", &decoded));  // three writes, each padded
  EXPECT_EQ(decoded, "ffofoo");
  EXPECT_FALSE(Base64Decode("Zm9", &decoded));     // a group cut short
  EXPECT_FALSE(Base64Decode("Zm9*", &decoded));    // not in the alphabet
  EXPECT_FALSE(Base64Decode("Z===", &decoded));    // too much padding
  EXPECT_FALSE(Base64Decode("Zg=a", &decoded));    // a character after the padding
  EXPECT_FALSE(Base64Decode("Zm9v\n", &decoded));  // whitespace is the caller's business
}

TEST(GrpcWebFraming, ContentTypesSelectBinaryOrText) {
  EXPECT_EQ(GrpcWebModeOf("application/grpc-web"), GrpcWebMode::kBinary);
  EXPECT_EQ(GrpcWebModeOf("application/grpc-web+proto"), GrpcWebMode::kBinary);
  EXPECT_EQ(GrpcWebModeOf("application/grpc-web-text"), GrpcWebMode::kText);
  EXPECT_EQ(GrpcWebModeOf("application/grpc-web-text+proto"), GrpcWebMode::kText);
  EXPECT_EQ(GrpcWebModeOf("application/grpc-web+json"), GrpcWebMode::kNone);
  EXPECT_EQ(GrpcWebModeOf("application/grpc"), GrpcWebMode::kNone);
  EXPECT_EQ(GrpcWebModeOf("application/json"), GrpcWebMode::kNone);
}

}  // namespace
}  // namespace armature::server::gateway
