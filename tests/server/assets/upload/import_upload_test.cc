// The ImportAsset chunk protocol without a server: how messages assemble into
// the upload, and which sequences are refused with which message.
#include <gtest/gtest.h>

#include "server/assets/upload/import_upload.h"

namespace armature::server {
namespace {

v1::ImportAssetRequest Header(const std::string& filename, const std::string& data) {
  v1::ImportAssetRequest m;
  m.set_filename(filename);
  m.set_name("walk");
  m.set_format("bvh");
  m.set_replace(true);
  m.set_data(data);
  return m;
}

v1::ImportAssetRequest Chunk(const std::string& data, const std::string& resource = "") {
  v1::ImportAssetRequest m;
  m.set_data(data);
  m.set_resource(resource);
  return m;
}

TEST(ImportUpload, AssemblesTheMainFileAndResourcesFromChunks) {
  ImportUpload upload(1000);
  ASSERT_TRUE(upload.Add(Header("walk.gltf", "ab")).ok());
  ASSERT_TRUE(upload.Add(Chunk("cd")).ok());
  ASSERT_TRUE(upload.Add(Chunk("01", "a.bin")).ok());
  ASSERT_TRUE(upload.Add(Chunk("23")).ok());
  ASSERT_TRUE(upload.Add(Chunk("xy", "b.bin")).ok());
  ASSERT_TRUE(upload.Add(Chunk("")).ok());  // an empty chunk is harmless
  EXPECT_EQ(upload.messages(), 6);
  EXPECT_EQ(upload.received_bytes(), 10 + 5 + 5);  // data, and the resource names
  auto import = std::move(upload).Finish();
  ASSERT_TRUE(import.ok()) << import.status().message();
  EXPECT_EQ(import->filename, "walk.gltf");
  EXPECT_EQ(import->name, "walk");
  EXPECT_EQ(import->format, "bvh");
  EXPECT_TRUE(import->replace);
  EXPECT_EQ(import->bytes, "abcd");
  ASSERT_EQ(import->resources.size(), 2u);
  EXPECT_EQ(import->resources.at("a.bin"), "0123");
  EXPECT_EQ(import->resources.at("b.bin"), "xy");
}

TEST(ImportUpload, NoMessagesIsInvalid) {
  auto import = ImportUpload(1000).Finish();
  ASSERT_FALSE(import.ok());
  EXPECT_EQ(import.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(import.status().message(), "no data: the upload had no messages");
}

TEST(ImportUpload, UpToTheLimitIsAcceptedOneByteMoreIsNot) {
  ImportUpload exact(6);
  ASSERT_TRUE(exact.Add(Header("a.bvh", "abc")).ok());
  EXPECT_TRUE(exact.Add(Chunk("def")).ok());
  ImportUpload over(6);
  ASSERT_TRUE(over.Add(Header("a.bvh", "abc")).ok());
  const Status st = over.Add(Chunk("defg"));
  EXPECT_EQ(st.code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(st.message(), "upload exceeds the limit of 6 bytes (--max-upload-mb)");
}

// Before, resource names were not counted: endless messages each naming a
// new empty resource grew the server's memory without bound.
TEST(ImportUpload, ResourceNamesCountAgainstTheLimit) {
  ImportUpload upload(100);
  ASSERT_TRUE(upload.Add(Header("a.gltf", "{}")).ok());
  Status st;
  int accepted = 0;
  for (int i = 0; i < 1000 && st.ok(); ++i) {
    st = upload.Add(Chunk("", "resource-" + std::to_string(i)));
    if (st.ok()) ++accepted;
  }
  EXPECT_EQ(st.code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(accepted, 9);  // 2 + 9 × 10 bytes fit in 100, the tenth does not
}

TEST(ImportUpload, HeaderFieldsAfterTheFirstMessageAreRefused) {
  for (const char* field : {"filename", "name", "format", "replace", "precision"}) {
    ImportUpload upload(1000);
    ASSERT_TRUE(upload.Add(Header("a.bvh", "abc")).ok());
    v1::ImportAssetRequest late = Chunk("def");
    if (std::string(field) == "filename") late.set_filename("b.bvh");
    if (std::string(field) == "name") late.set_name("b");
    if (std::string(field) == "format") late.set_format("obj");
    if (std::string(field) == "replace") late.set_replace(true);
    if (std::string(field) == "precision") late.set_precision("exact");
    const Status st = upload.Add(late);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << field;
    EXPECT_EQ(st.message(), std::string("message 2: ") + field + " belongs in the first message only");
  }
}

// precision is read once, in the first message, before the file arrives: a
// bound in (0, 10] cm or "exact"; anything else is INVALID_ARGUMENT naming it.
TEST(ImportUpload, PrecisionIsABoundOrExactAndIsCheckedInTheFirstMessage) {
  for (const char* good : {"", "exact", "0.01", "10"}) {
    ImportUpload upload(1000);
    v1::ImportAssetRequest first = Header("a.bvh", "abc");
    first.set_precision(good);
    ASSERT_TRUE(upload.Add(first).ok()) << good;
    auto import = std::move(upload).Finish();
    ASSERT_TRUE(import.ok());
    EXPECT_EQ(import->precision, good);
  }
  for (const char* bad : {"0", "-1", "nan", "10.01", "1e9", "fine"}) {
    ImportUpload upload(1000);
    v1::ImportAssetRequest first = Header("a.bvh", "abc");
    first.set_precision(bad);
    const Status st = upload.Add(first);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << bad;
    EXPECT_EQ(st.message().rfind("precision: '" + std::string(bad) + "' is not a bound", 0), 0u) << st.message();
  }
}

TEST(ImportUpload, AFirstMessageStartingAResourceIsRefused) {
  ImportUpload upload(1000);
  const Status st = upload.Add(Chunk("abc", "scene.bin"));
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message(),
            "message 1: starts resource 'scene.bin', but the first message starts the main file (send resources "
            "after it)");
}

// Before, a resource sent twice had its second part appended to the first.
TEST(ImportUpload, AResourceSentTwiceIsRefused) {
  ImportUpload upload(1000);
  ASSERT_TRUE(upload.Add(Header("a.gltf", "{}")).ok());
  ASSERT_TRUE(upload.Add(Chunk("1", "scene.bin")).ok());
  ASSERT_TRUE(upload.Add(Chunk("2", "other.bin")).ok());
  const Status st = upload.Add(Chunk("3", "scene.bin"));
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message(), "message 4: resource 'scene.bin' was already sent");
}

TEST(ImportUpload, NamesQuotedInMessagesAreEscaped) {
  ImportUpload upload(1000);
  const Status st = upload.Add(Chunk("", std::string("a\xff\n", 3)));
  EXPECT_EQ(st.message(),
            "message 1: starts resource 'a\\xff\\x0a', but the first message starts the main file (send resources "
            "after it)");
}

}  // namespace
}  // namespace armature::server
