// Materials, UVs and images through glTF import and export: CesiumMan's
// textured material and TEXCOORD_0, RobotExpressive's three colour
// materials, the image bytes kept exactly as stored (never decoded), and
// hostile material data refused with the field named.
#include <algorithm>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "armature/engine/io/gltf/gltf.h"
#include "armature/engine/io/gltf/gltf_writer.h"
#include "armature/engine/mesh/mesh.h"
#include "../testing/mesh_test_util.h"

namespace armature {
namespace {

using Json = nlohmann::json;

const char kCesium[] = "gltf/cesium_man.gltf";
constexpr size_t kCesiumVertices = 3273;
constexpr size_t kCesiumJpegBytes = 209908;  // the data: URI's bytes, decoded

std::optional<std::string> CesiumText() { return test_util::ReadFileBytes(test_util::SharedData(kCesium)); }

#define SKIP_WITHOUT(text) \
  if (!(text)) GTEST_SKIP() << "shared data " << test_util::SharedData(kCesium).string() << " is absent"

const Mesh& OnlyMesh(const AssetContents& contents) { return *contents.meshes.at(0).mesh; }

// CesiumMan with one edit to its JSON.
StatusOr<AssetContents> ParseEdited(const std::string& text, const std::function<void(Json&)>& edit) {
  Json j = Json::parse(text);
  edit(j);
  return ParseGltf(j.dump(), false, "cesium");
}

void ExpectCesiumMaterial(const Mesh& mesh) {
  ASSERT_EQ(mesh.uvs.size(), kCesiumVertices);
  // The accessor's declared min and max are reached, and bound every UV.
  float lo_u = 1, lo_v = 1, hi_u = 0, hi_v = 0;
  for (const Eigen::Vector2f& uv : mesh.uvs)
    lo_u = std::min(lo_u, uv.x()), lo_v = std::min(lo_v, uv.y()), hi_u = std::max(hi_u, uv.x()),
    hi_v = std::max(hi_v, uv.y());
  EXPECT_FLOAT_EQ(lo_u, 0.014079390093684196f);
  EXPECT_FLOAT_EQ(lo_v, 0.008445978164672852f);
  EXPECT_FLOAT_EQ(hi_u, 0.990805983543396f);
  EXPECT_FLOAT_EQ(hi_v, 0.9880298972129822f);
  ASSERT_EQ(mesh.materials.size(), 1u);
  ASSERT_EQ(mesh.material_groups.size(), 1u);
  EXPECT_EQ(mesh.material_groups[0].triangle_count, mesh.triangle_count());
  EXPECT_EQ(mesh.material_groups[0].material, 0);
  const Material& m = *mesh.materials[0];
  EXPECT_EQ(m.name, "Cesium_Man-effect");
  EXPECT_EQ(m.metallic_factor, 0.0);
  EXPECT_EQ(m.roughness_factor, 1.0);
  EXPECT_EQ(m.base_color_factor, (std::array<double, 4>{1, 1, 1, 1}));
  ASSERT_TRUE(m.base_color_texture.present());
  EXPECT_FALSE(m.normal_texture.present());
  EXPECT_EQ(m.base_color_texture.sampler.mag_filter, 9729);  // LINEAR
  EXPECT_EQ(m.base_color_texture.sampler.min_filter, 9986);  // NEAREST_MIPMAP_LINEAR
  EXPECT_EQ(m.base_color_texture.sampler.wrap_s, 10497);
  ASSERT_EQ(m.images.size(), 1u);
  const MaterialImage& image = *m.images[static_cast<size_t>(m.base_color_texture.image)];
  EXPECT_EQ(image.mime_type, "image/jpeg");
  EXPECT_EQ(image.bytes.size(), kCesiumJpegBytes);
  EXPECT_EQ(image.bytes.substr(0, 3), "\xFF\xD8\xFF");
}

TEST(GltfMaterial, CesiumManKeepsUvsMaterialAndJpeg) {
  const auto text = CesiumText();
  SKIP_WITHOUT(text);
  auto contents = ParseGltf(*text, false, "cesium");
  ASSERT_TRUE(contents.ok()) << contents.status().message();
  ExpectCesiumMaterial(OnlyMesh(*contents));
}

TEST(GltfMaterial, RobotExpressiveKeepsItsThreeColourMaterials) {
  const auto path = test_util::SharedData("gltf/RobotExpressive/RobotExpressive.glb");
  auto robot = test_util::LoadGltfFile(path, "robot");
  if (!robot.ok()) GTEST_SKIP() << "shared data " << path.string() << " is absent";
  std::set<const Material*> distinct;
  size_t groups = 0;
  for (const NamedMesh& m : robot->meshes) {
    ASSERT_FALSE(m.mesh->materials.empty()) << m.name;
    EXPECT_TRUE(m.mesh->uvs.empty()) << m.name;  // the robot has no TEXCOORD_0
    for (const auto& material : m.mesh->materials) distinct.insert(material.get());
    groups += m.mesh->material_groups.size();
  }
  ASSERT_EQ(distinct.size(), 3u);           // shared, not copied per mesh
  EXPECT_EQ(groups, robot->meshes.size());  // one primitive per mesh
  for (const Material* m : distinct) {
    EXPECT_TRUE(m->images.empty());
    EXPECT_DOUBLE_EQ(m->metallic_factor, 0.1);
    EXPECT_DOUBLE_EQ(m->roughness_factor, 0.9);
    if (m->name == "Main") EXPECT_DOUBLE_EQ(m->base_color_factor[0], 0.590328395366669);
  }
}

TEST(GltfMaterial, ExportWritesUvsMaterialAndTheSameImageBytes) {
  const auto text = CesiumText();
  SKIP_WITHOUT(text);
  auto cesium = ParseGltf(*text, false, "cesium");
  ASSERT_TRUE(cesium.ok()) << cesium.status().message();
  const Mesh* meshes[] = {&OnlyMesh(*cesium)};
  for (bool binary : {true, false}) {
    auto bytes = ExportGltf(*cesium->clips.at(0).clip, meshes, {.binary = binary});
    ASSERT_TRUE(bytes.ok()) << bytes.status().message();
    EXPECT_LE(bytes->size(), GltfExportByteEstimate(*cesium->clips.at(0).clip, meshes, binary));
    auto back = ParseGltf(*bytes, binary, "back");
    ASSERT_TRUE(back.ok()) << back.status().message();
    const Mesh& mesh = OnlyMesh(*back);
    ExpectCesiumMaterial(mesh);
    EXPECT_EQ(mesh.uvs, OnlyMesh(*cesium).uvs);
    EXPECT_EQ(mesh.materials[0]->images.at(0)->bytes, OnlyMesh(*cesium).materials[0]->images.at(0)->bytes);
  }
}

TEST(GltfMaterial, ImageOverTheLimitIsRefusedNamingIt) {
  const auto text = CesiumText();
  SKIP_WITHOUT(text);
  ImportLimits limits;
  limits.max_image_bytes = kCesiumJpegBytes - 1;
  auto refused = ParseGltf(*text, false, "cesium", {}, limits);
  EXPECT_EQ(refused.status().code(), StatusCode::kResourceExhausted);
  EXPECT_NE(
      refused.status().message().find("images[0]: 209908 bytes is over the import limit max_image_bytes = 209907"),
      std::string::npos)
      << refused.status().message();
  limits.max_image_bytes = kCesiumJpegBytes;
  EXPECT_TRUE(ParseGltf(*text, false, "cesium", {}, limits).ok());
}

void ExpectRefused(const StatusOr<AssetContents>& parsed, const std::string& part) {
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(parsed.status().message().find(part), std::string::npos) << parsed.status().message();
}

// A mesh of two primitives with different materials keeps a group per
// primitive, and the export writes them back as two primitives.
TEST(GltfMaterial, PrimitivesOfOneMeshKeepTheirOwnMaterials) {
  const auto text = CesiumText();
  SKIP_WITHOUT(text);
  auto two = ParseEdited(*text, [](Json& j) {
    Json red = j["materials"][0];
    red["name"] = "red";
    red["pbrMetallicRoughness"] = {{"baseColorFactor", {1, 0, 0, 1}}};
    j["materials"].push_back(red);
    Json second = j["meshes"][0]["primitives"][0];
    second["material"] = 1;
    j["meshes"][0]["primitives"].push_back(second);
  });
  ASSERT_TRUE(two.ok()) << two.status().message();
  const Mesh& mesh = OnlyMesh(*two);
  ASSERT_EQ(mesh.materials.size(), 2u);
  EXPECT_EQ(mesh.materials[1]->name, "red");
  EXPECT_FALSE(mesh.materials[1]->base_color_texture.present());
  ASSERT_EQ(mesh.material_groups.size(), 2u);
  const uint32_t half = static_cast<uint32_t>(mesh.triangle_count() / 2);
  EXPECT_EQ(mesh.material_groups[1].first_triangle, half);
  EXPECT_EQ(mesh.material_groups[1].triangle_count, half);
  EXPECT_EQ(mesh.material_groups[1].material, 1);
  EXPECT_EQ(mesh.uvs.size(), 2 * kCesiumVertices);
  const Mesh* meshes[] = {&mesh};
  auto bytes = ExportGltf(*two->clips.at(0).clip, meshes);
  ASSERT_TRUE(bytes.ok()) << bytes.status().message();
  auto back = ParseGltf(*bytes, true, "back");
  ASSERT_TRUE(back.ok()) << back.status().message();
  const Mesh& again = OnlyMesh(*back);
  ASSERT_EQ(again.material_groups.size(), 2u);
  EXPECT_EQ(again.material_groups[1].first_triangle, half);
  EXPECT_EQ(again.materials.at(1)->base_color_factor, (std::array<double, 4>{1, 0, 0, 1}));
  EXPECT_EQ(again.materials.at(0)->images.at(0)->bytes.size(), kCesiumJpegBytes);
}

TEST(GltfMaterial, HostileMaterialDataIsRefusedNamingTheField) {
  const auto text = CesiumText();
  SKIP_WITHOUT(text);
  ExpectRefused(ParseEdited(*text, [](Json& j) { j["textures"][0]["source"] = 5; }), "images[5] does not exist");
  ExpectRefused(ParseEdited(*text, [](Json& j) { j["materials"][0]["alphaMode"] = "GLOW"; }),
                "materials[0].alphaMode 'GLOW' is not OPAQUE, MASK or BLEND");
  ExpectRefused(ParseEdited(*text, [](Json& j) { j["meshes"][0]["primitives"][0]["material"] = 3; }),
                "materials[3] does not exist");
  // An image's bufferView past its buffer: refused before any byte is read.
  ExpectRefused(ParseEdited(*text,
                            [](Json& j) {
                              j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 253000}, {"byteLength", 1000}});
                              j["images"][0] = {{"bufferView", j["bufferViews"].size() - 1}, {"mimeType", "image/png"}};
                            }),
                "runs past its buffer of 253500 bytes");
}

TEST(GltfMaterial, AnImageNotProvidedDropsItsTextureWithAWarning) {
  const auto text = CesiumText();
  SKIP_WITHOUT(text);
  auto parsed = ParseEdited(*text, [](Json& j) { j["images"][0]["uri"] = "skin.jpg"; });
  ASSERT_TRUE(parsed.ok()) << parsed.status().message();
  const Mesh& mesh = OnlyMesh(*parsed);
  ASSERT_EQ(mesh.materials.size(), 1u);
  EXPECT_FALSE(mesh.materials[0]->base_color_texture.present());
  EXPECT_EQ(mesh.uvs.size(), kCesiumVertices);
  const auto& w = parsed->warnings;
  EXPECT_TRUE(std::any_of(w.begin(), w.end(), [](const std::string& s) {
    return s.find("images[0] uri 'skin.jpg' was not provided") != std::string::npos;
  }));
}

}  // namespace
}  // namespace armature
