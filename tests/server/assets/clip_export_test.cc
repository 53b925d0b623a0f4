// ExportClip's work over an in-memory catalog: the answer's size bounded
// before the work in the encoding it travels in (JSON: base64, 4 bytes per 3).
#include <gtest/gtest.h>

#include <string>

#include "../testing/demo_catalog.h"
#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/gltf/gltf_writer.h"
#include "server/assets/clip_export.h"

namespace armature::server {
namespace {

using test_util::DemoCatalog;

v1::ExportClipRequest Request(const std::string& format) {
  v1::ExportClipRequest request;
  request.set_clip("demo_walk");
  request.set_format(format);
  return request;
}

TEST(ClipExport, AFileThatFitsInBinaryButNotAsBase64JsonIsRefusedBeforeTheWork) {
  const auto catalog = DemoCatalog();
  const auto clip_keys = test_util::StoredKeys(*catalog->FindClip("demo_walk")->part);
  const Clip& clip = *clip_keys;
  for (const std::string format : {"bvh", "glb"}) {
    v1::ExportClipResponse answer;
    ASSERT_TRUE(ExportClip(*catalog, Limits{}, Request(format), &answer).ok()) << format;
    ASSERT_GT(answer.data().size(), 1000u) << format;
    // The writers' own estimates, which the bound is checked against (at least the file's size).
    const double file =
        static_cast<double>(format == "bvh" ? BvhExportByteEstimate(clip) : GltfExportByteEstimate(clip, {}, true));
    ASSERT_GE(file, static_cast<double>(answer.data().size())) << format;

    Limits limits;
    limits.max_message_bytes = static_cast<int64_t>(file * 1.15);  // room for the file, not for its base64
    v1::ExportClipResponse binary;
    EXPECT_TRUE(ExportClip(*catalog, limits, Request(format), &binary, ReplyEncoding::kProtobuf).ok()) << format;
    EXPECT_EQ(binary.data(), answer.data()) << format;

    v1::ExportClipResponse json;
    const Status st = ExportClip(*catalog, limits, Request(format), &json, ReplyEncoding::kJson);
    EXPECT_EQ(st.code(), StatusCode::kResourceExhausted) << format;
    EXPECT_NE(st.message().find("base64 in JSON"), std::string::npos) << st.message();
    EXPECT_NE(st.message().find("--max-message-mb"), std::string::npos) << st.message();
    EXPECT_TRUE(json.data().empty()) << format;

    limits.max_message_bytes = static_cast<int64_t>(file * 1.45);  // room for the base64 too
    EXPECT_TRUE(ExportClip(*catalog, limits, Request(format), &json, ReplyEncoding::kJson).ok()) << format;
    EXPECT_EQ(json.data(), answer.data()) << format;
  }
}

TEST(ClipExport, BadRequestsNameTheField) {
  const auto catalog = DemoCatalog();
  v1::ExportClipResponse answer;
  Status st = ExportClip(*catalog, Limits{}, Request("fbx"), &answer);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message().rfind("format:", 0), 0u) << st.message();
  v1::ExportClipRequest with_meshes = Request("bvh");
  with_meshes.set_with_meshes(true);
  st = ExportClip(*catalog, Limits{}, with_meshes, &answer);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message().rfind("with_meshes:", 0), 0u) << st.message();
  v1::ExportClipRequest missing = Request("bvh");
  missing.set_clip("nope");
  EXPECT_EQ(ExportClip(*catalog, Limits{}, missing, &answer).code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace armature::server
