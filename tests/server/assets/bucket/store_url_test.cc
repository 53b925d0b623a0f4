#include "server/assets/bucket/store_url.h"

#include <gtest/gtest.h>

namespace armature::server {
namespace {

TEST(StoreUrl, HttpWithPortBucketAndPrefix) {
  auto loc = ParseStoreUrl("s3://127.0.0.1:9000/assets/team/a");
  ASSERT_TRUE(loc.ok()) << loc.status().message();
  EXPECT_EQ(loc->scheme, "http");
  EXPECT_EQ(loc->host, "127.0.0.1");
  EXPECT_EQ(loc->port, 9000);
  EXPECT_EQ(loc->bucket, "assets");
  EXPECT_EQ(loc->prefix, "team/a/");
  EXPECT_EQ(loc->Endpoint(), "http://127.0.0.1:9000");
}

TEST(StoreUrl, HttpsDefaultsToPort443) {
  auto loc = ParseStoreUrl("s3+https://s3.eu-west-1.amazonaws.com/my.bucket.with.dots");
  ASSERT_TRUE(loc.ok()) << loc.status().message();
  EXPECT_EQ(loc->scheme, "https");
  EXPECT_EQ(loc->port, 443);
  EXPECT_EQ(loc->bucket, "my.bucket.with.dots");
  EXPECT_EQ(loc->prefix, "");
}

TEST(StoreUrl, EmptyAndSlashOnlyPrefixesAreTheRoot) {
  for (const char* url : {"s3://h:1/bkt", "s3://h:1/bkt/", "s3://h:1/bkt//", "s3://h:1/bkt///"}) {
    auto loc = ParseStoreUrl(url);
    ASSERT_TRUE(loc.ok()) << url;
    EXPECT_EQ(loc->prefix, "") << url;
  }
  EXPECT_EQ(ParseStoreUrl("s3://h:1/bkt//a//b/")->prefix, "a/b/");
}

TEST(StoreUrl, RejectsBadSchemesPortsAndBucketNames) {
  for (const char* url : {"http://h:1/bkt", "s3://h:0/bkt", "s3://h:x/bkt", "s3://:1/bkt", "s3://h:1/",
                          "s3://h:1/Upper", "s3://h:1/ab", "s3://h:1/-bucket", "s3://h:1/bucket_underscore"}) {
    auto loc = ParseStoreUrl(url);
    EXPECT_EQ(loc.status().code(), StatusCode::kInvalidArgument) << url;
  }
  EXPECT_NE(ParseStoreUrl("s3://h:1/Upper").status().message().find("not a valid S3 bucket name"), std::string::npos);
}

}  // namespace
}  // namespace armature::server
