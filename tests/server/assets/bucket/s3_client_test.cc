// The S3 client against a real S3-compatible server (s3rver on a loopback port).
#include "server/assets/bucket/s3_client.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>

#include "tests/common/s3rver_process.h"

namespace armature::server {
namespace {

using armature::testing::S3rverProcess;

AwsCredentials S3rverKey() { return {.access_key_id = "S3RVER", .secret_access_key = "S3RVER", .source = "test"}; }

S3Client ClientOf(const S3rverProcess& s3, const std::string& bucket, AwsCredentials creds = S3rverKey()) {
  return S3Client(*ParseStoreUrl(s3.Url(bucket)), std::move(creds),
                  {std::chrono::milliseconds(1000), std::chrono::milliseconds(5000)});
}

TEST(S3Client, PutGetListDeleteOnADottedBucket) {
  S3rverProcess s3({"assets.v1.example"});
  S3Client client = ClientOf(s3, "assets.v1.example");
  std::string binary(300000, '\0');
  for (size_t i = 0; i < binary.size(); ++i) binary[i] = static_cast<char>(i * 7919 % 251);
  ASSERT_TRUE(client.Put("p/a b+c.bin", binary).ok());
  ASSERT_TRUE(client.Put("p/x", "small").ok());
  ASSERT_TRUE(client.Put("q/y", "other").ok());
  auto got = client.Get("p/a b+c.bin");
  ASSERT_TRUE(got.ok()) << got.status().message();
  EXPECT_EQ(*got, binary);
  auto listed = client.List("p/");
  ASSERT_TRUE(listed.ok()) << listed.status().message();
  ASSERT_EQ(listed->size(), 2u);
  EXPECT_EQ((*listed)[0].key, "p/a b+c.bin");
  EXPECT_EQ((*listed)[0].size, 300000);
  EXPECT_EQ((*listed)[1].key, "p/x");
  ASSERT_TRUE(client.Delete("p/x").ok());
  EXPECT_EQ(client.Get("p/x").status().code(), StatusCode::kNotFound);
  EXPECT_EQ(client.List("p/")->size(), 1u);
}

TEST(S3Client, ListReadsEveryPage) {
  S3rverProcess s3({"paged"});
  S3Client client = ClientOf(s3, "paged");
  client.set_page_size(3);
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(client.Put("k/" + std::to_string(100 + i), "v").ok());
  auto listed = client.List("k/");
  ASSERT_TRUE(listed.ok()) << listed.status().message();
  ASSERT_EQ(listed->size(), 10u);
  for (int i = 0; i < 10; ++i) EXPECT_EQ((*listed)[i].key, "k/" + std::to_string(100 + i));
}

TEST(S3Client, AnUnknownAccessKeyIsDeniedAndSaysSo) {
  S3rverProcess s3({"bucket"});
  S3Client client = ClientOf(s3, "bucket", {.access_key_id = "NOBODY", .secret_access_key = "x", .source = "test"});
  const Status st = client.List("").status();
  EXPECT_EQ(st.code(), StatusCode::kPermissionDenied);
  EXPECT_NE(st.message().find("InvalidAccessKeyId"), std::string::npos) << st.message();
  EXPECT_NE(st.message().find("check the credentials"), std::string::npos) << st.message();
}

TEST(S3Client, AMissingBucketIsAFailedPrecondition) {
  S3rverProcess s3({"bucket"});
  S3Client client = ClientOf(s3, "no-such-bucket");
  const Status st = client.List("").status();
  EXPECT_EQ(st.code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(st.message().find("NoSuchBucket"), std::string::npos) << st.message();
}

TEST(S3Client, AnUnreachableEndpointIsUnavailableWithinTheTimeout) {
  int port = 0;
  {
    S3rverProcess s3({"bucket"});
    port = s3.port();
  }  // stopped: nothing listens there now
  S3Client client(*ParseStoreUrl("s3://127.0.0.1:" + std::to_string(port) + "/bucket"), S3rverKey());
  const auto start = std::chrono::steady_clock::now();
  const Status st = client.Put("k", "v");
  EXPECT_EQ(st.code(), StatusCode::kUnavailable);
  EXPECT_NE(st.message().find("http://127.0.0.1:" + std::to_string(port) + "/bucket"), std::string::npos)
      << st.message();
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(3));
  // A server that takes the connection and never answers: the total timeout bounds it.
  const int silent = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof addr;
  ASSERT_EQ(::bind(silent, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  ASSERT_EQ(::listen(silent, 8), 0);  // the kernel completes handshakes; nobody ever reads
  ASSERT_EQ(::getsockname(silent, reinterpret_cast<sockaddr*>(&addr), &len), 0);
  S3Client stuck(*ParseStoreUrl("s3://127.0.0.1:" + std::to_string(ntohs(addr.sin_port)) + "/bucket"), S3rverKey(),
                 {std::chrono::milliseconds(300), std::chrono::milliseconds(1000)});
  const auto t0 = std::chrono::steady_clock::now();
  const Status timed_out = stuck.Get("k").status();
  const auto waited = std::chrono::steady_clock::now() - t0;
  ::close(silent);
  EXPECT_EQ(timed_out.code(), StatusCode::kUnavailable) << timed_out.message();
  EXPECT_GE(waited, std::chrono::milliseconds(900));
  EXPECT_LT(waited, std::chrono::milliseconds(2500));
}

TEST(S3Client, UriEncodingAsSigV4Wants) {
  EXPECT_EQ(UriEncode("a b/c+d~e_f.g-h", true), "a%20b/c%2Bd~e_f.g-h");
  EXPECT_EQ(UriEncode("a/b=", false), "a%2Fb%3D");
}

}  // namespace
}  // namespace armature::server
