// glTF import against hostile input: accessor bounds that wrap 64 bits, GLB
// chunk lengths that lie, and sizes checked against ImportLimits before
// anything is decoded or allocated.
#include <chrono>
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "armature/engine/io/asset.h"
#include "armature/engine/mesh/mesh.h"
#include "armature/base/utf8.h"

namespace armature {
namespace {

void U32(std::string* s, uint32_t v) { s->append(reinterpret_cast<const char*>(&v), 4); }

// A GLB container around `json` (padded) and `bin`.
std::string Glb(std::string json, const std::string& bin) {
  while (json.size() % 4) json.push_back(' ');
  std::string glb = "glTF";
  U32(&glb, 2);
  U32(&glb, static_cast<uint32_t>(20 + json.size() + 8 + bin.size()));
  U32(&glb, static_cast<uint32_t>(json.size()));
  U32(&glb, 0x4E4F534A);
  glb += json;
  U32(&glb, static_cast<uint32_t>(bin.size()));
  U32(&glb, 0x004E4942);
  return glb + bin;
}

// One triangle: three VEC3 floats in a 36-byte buffer.
std::string TriangleBin() {
  const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  return std::string(reinterpret_cast<const char*>(v), sizeof v);
}

// A mesh on a node; `accessors` and `extra` (more top-level members) are spliced in.
std::string Json(const std::string& accessors,
                 const std::string& mesh = R"({"primitives":[{"attributes":{"POSITION":0}}]})",
                 const std::string& extra = "") {
  return R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":36}],"bufferViews":[{"buffer":0,"byteLength":36}],)"
         R"("accessors":)" +
         accessors + R"(,"meshes":[)" + mesh + R"(],"nodes":[{"mesh":0}])" + extra + "}";
}

StatusOr<AssetContents> Import(const std::string& json, const ImportLimits& limits = {}) {
  return ParseAsset(AssetFormat::kGlb, Glb(json, TriangleBin()), "m", {}, limits);
}

void ExpectError(const StatusOr<AssetContents>& r, StatusCode code, const std::string& fragment) {
  ASSERT_FALSE(r.ok()) << "expected an error containing: " << fragment;
  EXPECT_EQ(r.status().code(), code) << r.status().message();
  EXPECT_NE(r.status().message().find(fragment), std::string::npos) << r.status().message();
  EXPECT_TRUE(IsValidUtf8(r.status().message()));
}

const char* kPosition = R"([{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}])";

TEST(GltfHardening, TheBaseFileImports) {
  auto r = Import(Json(kPosition));
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_EQ(r->meshes[0].mesh->vertex_count(), 3u);
}

TEST(GltfHardening, AccessorByteOffsetsNear2To64AreRefusedNotWrapped) {
  // offset + (count − 1)·stride + element wrapped to 24 (≤ 36) for the first:
  // the old check passed and the reader read 12 bytes before the buffer.
  for (const char* offset : {"18446744073709551604", "18446744073709551615", "9223372036854775808", "40"}) {
    const std::string accessors = std::string(R"([{"bufferView":0,"byteOffset":)") + offset +
                                  R"(,"componentType":5126,"count":3,"type":"VEC3"}])";
    ExpectError(Import(Json(accessors)), StatusCode::kInvalidArgument,
                std::string("POSITION: accessor 0 byteOffset ") + offset + " is beyond the end of bufferView 0");
  }
  // In range but too long for the view: the needed bytes are named.
  ExpectError(Import(Json(R"([{"bufferView":0,"byteOffset":4,"componentType":5126,"count":3,"type":"VEC3"}])")),
              StatusCode::kInvalidArgument, "accessor 0 needs 40 bytes of bufferView 0 but it has 36 (byteOffset 4");
}

TEST(GltfHardening, GlbChunkLengthsAreCheckedBeforeTinygltf) {
  const std::string good = Glb(Json(kPosition), TriangleBin());
  ASSERT_TRUE(ParseAsset(AssetFormat::kGlb, good, "m").ok());
  const size_t bin_header = good.size() - 36 - 8;

  // BIN chunk 8 bytes longer than what follows it: tinygltf 2.7.0 read past the end.
  std::string lying_bin = good;
  const uint32_t long_bin = 44;
  std::memcpy(&lying_bin[bin_header], &long_bin, 4);
  ExpectError(ParseAsset(AssetFormat::kGlb, lying_bin, "m"), StatusCode::kInvalidArgument,
              "glb: BIN chunk length 44 at byte " + std::to_string(bin_header) + " runs past the header's length");

  std::string lying_json = good;
  const uint32_t long_json = 1u << 30;
  std::memcpy(&lying_json[12], &long_json, 4);
  ExpectError(ParseAsset(AssetFormat::kGlb, lying_json, "m"), StatusCode::kInvalidArgument,
              "glb: JSON chunk length 1073741824 at byte 12 runs past");

  std::string lying_length = good;
  const uint32_t long_file = static_cast<uint32_t>(good.size() + 1);
  std::memcpy(&lying_length[8], &long_file, 4);
  ExpectError(ParseAsset(AssetFormat::kGlb, lying_length, "m"), StatusCode::kInvalidArgument,
              "glb: header length " + std::to_string(good.size() + 1) + " does not fit the file's");

  ExpectError(ParseAsset(AssetFormat::kGlb, good.substr(0, 19), "m"), StatusCode::kInvalidArgument, "too few");
  ExpectError(ParseAsset(AssetFormat::kGlb, good.substr(0, bin_header + 4), "m"), StatusCode::kInvalidArgument,
              "glb: header length");
}

TEST(GltfHardening, AccessorsWithoutBufferViewHaveAByteCap) {
  // 2^26 normals that no byte of the file pays for (the old reader
  // allocated 2.4 GB for them before comparing their count with POSITION's).
  const auto start = std::chrono::steady_clock::now();
  ExpectError(Import(Json(R"([{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},)"
                          R"({"componentType":5126,"count":67108864,"type":"VEC3"}])",
                          R"({"primitives":[{"attributes":{"POSITION":0,"NORMAL":1}}]})")),
              StatusCode::kResourceExhausted,
              "NORMAL: accessor 1 has no bufferView: count 67108864 × 12 bytes = 805306368 is over the import "
              "limit max_unbacked_accessor_bytes = 67108864");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));

  ImportLimits limits;
  limits.max_unbacked_accessor_bytes = 35;
  ExpectError(Import(Json(R"([{"componentType":5126,"count":3,"type":"VEC3"}])"), limits),
              StatusCode::kResourceExhausted, "max_unbacked_accessor_bytes = 35");
  limits.max_unbacked_accessor_bytes = 36;
  auto zeros = Import(Json(R"([{"componentType":5126,"count":3,"type":"VEC3"}])"), limits);
  EXPECT_NE(zeros.status().code(), StatusCode::kResourceExhausted) << zeros.status().message();
}

TEST(GltfHardening, DecodedValuesHaveABudgetPerImport) {
  ImportLimits limits;
  limits.max_accessor_values = 8;  // the 9 POSITION values
  ExpectError(Import(Json(kPosition), limits), StatusCode::kResourceExhausted,
              "POSITION: accessor 0: count 3 × 3 components, with the 0 values read before, 9 is over the import "
              "limit max_accessor_values = 8");
}

// `meshes` meshes on one accessor of `count` VEC3 zeros without a bufferView.
std::string SharedAccessorMeshes(int meshes, int count) {
  std::string list;
  for (int m = 0; m < meshes; ++m)
    list += std::string(m ? "," : "") + R"({"primitives":[{"attributes":{"POSITION":0}}]})";
  return R"({"asset":{"version":"2.0"},"accessors":[{"componentType":5126,"count":)" + std::to_string(count) +
         R"(,"type":"VEC3"}],"meshes":[)" + list + "]}";
}

TEST(GltfHardening, MeshesSharingAnAccessorCountOncePerUseBeforeDecoding) {
  // Each mesh's estimate (vertices × 84 bytes: 76 per vertex, 8 per implicit
  // index) is charged before it is decoded, so the third is refused undecoded.
  ImportLimits limits;
  limits.max_decoded_bytes = 2 * 1000 * 84;  // room for two of the eight
  ExpectError(ParseAsset(AssetFormat::kGltf, SharedAccessorMeshes(8, 1000), "bomb", {}, limits),
              StatusCode::kResourceExhausted,
              "meshes[2].primitives[0]: the estimated memory of the parts decoded so far, 252000 is over the "
              "import limit max_decoded_bytes = 168000 bytes");
  // The bomb: 8 meshes of 4,999,998 vertices, under every per-accessor cap
  // (2.77 GB when decoded), refused at the default 1 GiB before its third mesh.
  ExpectError(ParseAsset(AssetFormat::kGltf, SharedAccessorMeshes(8, 4999998), "bomb", {}, {}),
              StatusCode::kResourceExhausted, "meshes[2].primitives[0]: the estimated memory");
}

TEST(GltfHardening, MorphTargetsTimesVerticesIsCappedBeforeDecoding) {
  // 200 empty targets on 1M (unbacked, zero) vertices: 2·10^8 > 2^27.
  std::string targets = "[";
  for (int t = 0; t < 200; ++t) targets += std::string(t ? "," : "") + "{}";
  targets += "]";
  const auto start = std::chrono::steady_clock::now();
  ExpectError(Import(Json(R"([{"componentType":5126,"count":1000000,"type":"VEC3"}])",
                          R"({"primitives":[{"attributes":{"POSITION":0},"targets":)" + targets + "}]}")),
              StatusCode::kResourceExhausted,
              "meshes[0].primitives[0].targets: 200 morph targets × 1000000 vertices = 200000000 is over the import "
              "limit max_morph_target_vertices = 134217728");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
}

TEST(GltfHardening, MeshVerticesAreCappedBeforeDecoding) {
  ImportLimits limits;
  limits.max_mesh_vertices = 2;
  ExpectError(Import(Json(kPosition), limits), StatusCode::kResourceExhausted,
              "POSITION: 3 vertices is over the import limit max_mesh_vertices = 2");
}

// An animation of node 0's translation by sampler 0 (input accessor 1, output accessor 2).
std::string Animated(const std::string& input, const std::string& extra_channels = "") {
  return Json(
      std::string("[") + R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},)" + input +
          R"(,{"bufferView":0,"componentType":5126,"count":2,"type":"VEC3"}])",
      R"({"primitives":[{"attributes":{"POSITION":0}}]})",
      R"(,"animations":[{"samplers":[{"input":1,"output":2}],"channels":[{"sampler":0,"target":{"node":0,"path":"translation"}})" +
          extra_channels + "]}]");
}

TEST(GltfHardening, AnimationKeysAreCappedBeforeDecoding) {
  // 2^28 keys without a bufferView: the old reader spent 4.6 GB and seconds before refusing them.
  const auto start = std::chrono::steady_clock::now();
  ExpectError(Import(Animated(R"({"componentType":5126,"count":268435456,"type":"SCALAR"})")),
              StatusCode::kResourceExhausted,
              "animations[0].samplers[0].input: accessor 1: key count 268435456 is over the import limit "
              "max_clip_frames = 1000000");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));

  // Keys summed over the clip's tracks: 2 channels × 2 keys (times 0 and 1: floats 2 and 3 of the buffer).
  const std::string keys = R"({"bufferView":0,"byteOffset":8,"componentType":5126,"count":2,"type":"SCALAR"})";
  const std::string second = R"(,{"sampler":0,"target":{"node":0,"path":"scale"}})";
  auto within = Import(Animated(keys, second));
  ASSERT_TRUE(within.ok()) << within.status().message();
  ImportLimits limits;
  limits.max_clip_keys = 3;
  ExpectError(Import(Animated(keys, second), limits), StatusCode::kResourceExhausted,
              "keys of the clip's tracks 4 is over the import limit max_clip_keys = 3");
}

TEST(GltfHardening, JsonErrorsQuotingBytesThatAreNotUtf8AreEscaped) {
  const std::string json = Json(kPosition, R"({"name":"m)"
                                           "\xff\xfe"
                                           R"(","primitives":[{"attributes":{"POSITION":0}}]})");
  auto r = Import(json);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(IsValidUtf8(r.status().message())) << r.status().message();
}

}  // namespace
}  // namespace armature
