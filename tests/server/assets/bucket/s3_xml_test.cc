#include "server/assets/bucket/s3_xml.h"

#include <gtest/gtest.h>

namespace armature::server {
namespace {

TEST(S3Xml, ListPageKeysSizesAndContinuation) {
  const char* xml = R"(<?xml version="1.0" encoding="UTF-8"?>
<ListBucketResult><Name>b</Name><IsTruncated>true</IsTruncated>
<Contents><Key>p/a&amp;b</Key><ETag>&quot;x&quot;</ETag><Size>12</Size></Contents>
<Contents><Key>p/c&lt;d</Key><Size>0</Size></Contents>
<NextContinuationToken>tok&amp;en==</NextContinuationToken></ListBucketResult>)";
  auto page = ParseListPage(xml);
  ASSERT_TRUE(page.ok());
  ASSERT_EQ(page->entries.size(), 2u);
  EXPECT_EQ(page->entries[0].key, "p/a&b");
  EXPECT_EQ(page->entries[0].size, 12);
  EXPECT_EQ(page->entries[1].key, "p/c<d");
  EXPECT_TRUE(page->truncated);
  EXPECT_EQ(page->next_token, "tok&en==");
}

TEST(S3Xml, ErrorCodeAndMessage) {
  const char* xml = "<Error><Code>NoSuchBucket</Code><Message>The specified bucket does not exist</Message></Error>";
  EXPECT_EQ(XmlText(xml, "Code"), "NoSuchBucket");
  EXPECT_EQ(XmlText(xml, "Message"), "The specified bucket does not exist");
  EXPECT_EQ(XmlText(xml, "Missing"), "");
  EXPECT_EQ(ParseListPage(xml).status().code(), StatusCode::kInternal);
}

}  // namespace
}  // namespace armature::server
