// Materials, UVs and images through the API, on a real armature-server:
// CesiumMan's UVs and material groups in GetMeshGeometry, its material from
// GetMaterial (gRPC and REST), and its JPEG from GetMaterialImage exactly as
// the file stored it (REST: the bytes with Content-Type image/jpeg). Bad
// indices are INVALID_ARGUMENT naming the field and the count.
#include <string>
#include <vector>

// The engine (Eigen) before httplib.h, whose system headers define a macro
// that breaks Eigen's product kernels.
#include "armature/engine/io/asset.h"
#include "armature/engine/mesh/mesh.h"
#include "engine/testing/mesh_test_util.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "support/client_helpers.h"

namespace armature::testing {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

class Materials : public ::testing::Test {
 protected:
  void SetUp() override {
    if (SharedData("gltf/cesium_man.gltf").empty()) GTEST_SKIP() << "shared glTF data not found (ARMATURE_SHARED_DATA)";
    server_ = std::make_unique<ServerProcess>(data_.path(), std::vector<std::string>{"--no-demo"});
    client_ = std::make_unique<client::Client>(OptionsFor(*server_));
    mesh_ = client_->ImportFile(SharedData("gltf/cesium_man.gltf"), "cesium_man").asset().meshes(0).name();
    auto parsed = test_util::LoadGltfFile(SharedData("gltf/cesium_man.gltf"), "cesium_man");
    ASSERT_TRUE(parsed.ok()) << parsed.status().message();
    engine_ = parsed->meshes.at(0).mesh;
  }

  TempDir data_;
  std::unique_ptr<ServerProcess> server_;
  std::unique_ptr<client::Client> client_;
  std::string mesh_;
  std::shared_ptr<const Mesh> engine_;  // the same file parsed in this process
};

TEST_F(Materials, GeometryHasTheUvsAndTheMaterialGroups) {
  const v1::MeshGeometry geometry = client_->GetMeshGeometry(mesh_);
  ASSERT_EQ(geometry.uvs_size(), 2 * geometry.vertex_count());
  ASSERT_EQ(engine_->uvs.size(), 3273u);
  for (size_t v = 0; v < engine_->uvs.size(); ++v) {
    ASSERT_EQ(geometry.uvs(static_cast<int>(2 * v)), engine_->uvs[v].x()) << v;
    ASSERT_EQ(geometry.uvs(static_cast<int>(2 * v + 1)), engine_->uvs[v].y()) << v;
  }
  ASSERT_EQ(geometry.materials_size(), 1);
  EXPECT_EQ(geometry.materials(0), "Cesium_Man-effect");
  ASSERT_EQ(geometry.material_groups_size(), 1);
  EXPECT_EQ(geometry.material_groups(0).first_triangle(), 0u);
  EXPECT_EQ(geometry.material_groups(0).triangle_count(), static_cast<uint32_t>(geometry.triangles_size() / 3));
  EXPECT_EQ(geometry.material_groups(0).material(), 0);
}

TEST_F(Materials, GetMaterialAndItsImageAsStored) {
  const v1::Material material = client_->GetMaterial(mesh_, 0);
  EXPECT_EQ(material.name(), "Cesium_Man-effect");
  EXPECT_EQ(material.mesh(), mesh_);
  EXPECT_EQ(std::vector<double>(material.base_color_factor().begin(), material.base_color_factor().end()),
            (std::vector<double>{1, 1, 1, 1}));
  EXPECT_EQ(material.metallic_factor(), 0.0);
  EXPECT_EQ(material.roughness_factor(), 1.0);
  EXPECT_EQ(material.alpha_mode(), "OPAQUE");
  ASSERT_TRUE(material.has_base_color_texture());
  EXPECT_FALSE(material.has_normal_texture());
  EXPECT_EQ(material.base_color_texture().image(), 0);
  EXPECT_EQ(material.base_color_texture().sampler().mag_filter(), 9729);
  EXPECT_EQ(material.base_color_texture().sampler().min_filter(), 9986);
  ASSERT_EQ(material.images_size(), 1);
  EXPECT_EQ(material.images(0).mime_type(), "image/jpeg");
  EXPECT_EQ(material.images(0).byte_size(), 209908);

  const v1::MaterialImage image = client_->GetMaterialImage(mesh_, 0, 0);
  EXPECT_EQ(image.mime_type(), "image/jpeg");
  ASSERT_EQ(image.data().size(), 209908u);
  EXPECT_TRUE(image.data() == engine_->materials.at(0)->images.at(0)->bytes);  // byte for byte

  // REST: the material as JSON, the image as its own bytes and type.
  httplib::Client http("127.0.0.1", server_->http_port());
  const auto got = http.Get("/v1/meshes/" + mesh_ + "/materials/0");
  ASSERT_TRUE(got);
  ASSERT_EQ(got->status, 200) << got->body;
  const json j = json::parse(got->body);
  EXPECT_EQ(j["name"], "Cesium_Man-effect");
  EXPECT_EQ(j["baseColorTexture"]["image"], 0);
  EXPECT_EQ(j["images"][0]["mimeType"], "image/jpeg");
  const auto bytes = http.Get("/v1/meshes/" + mesh_ + "/materials/0/images/0");
  ASSERT_TRUE(bytes);
  ASSERT_EQ(bytes->status, 200);
  EXPECT_EQ(bytes->get_header_value("Content-Type"), "image/jpeg");
  EXPECT_TRUE(bytes->body == image.data());
}

TEST_F(Materials, BadIndicesAreRefusedNamingTheField) {
  const grpc::Status material = StatusOf([&] { client_->GetMaterial(mesh_, 1); });
  EXPECT_EQ(material.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(material.error_message(), "material: 1 is out of range (mesh '" + mesh_ + "' has 1 materials)");
  const grpc::Status image = StatusOf([&] { client_->GetMaterialImage(mesh_, 0, -1); });
  EXPECT_EQ(image.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(image.error_message(), "image: -1 is out of range (material 0 of mesh '" + mesh_ + "' has 1 images)");
  EXPECT_EQ(CodeOf([&] { client_->GetMaterial("nope", 0); }), grpc::StatusCode::NOT_FOUND);
  httplib::Client http("127.0.0.1", server_->http_port());
  const auto rest = http.Get("/v1/meshes/" + mesh_ + "/materials/0/images/7");
  ASSERT_TRUE(rest);
  EXPECT_EQ(rest->status, 400);
  EXPECT_NE(rest->body.find("image: 7 is out of range"), std::string::npos) << rest->body;
}

// --max-image-mb caps one image's stored bytes: CesiumMan's JPEG (over 100 KB)
// under a 0.05 MiB cap is refused, the flag named, and nothing is stored.
TEST(MaterialLimits, AnImageOverMaxImageMbIsRefusedNamingTheFlag) {
  if (SharedData("gltf/cesium_man.gltf").empty()) GTEST_SKIP() << "shared glTF data not found (ARMATURE_SHARED_DATA)";
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-image-mb", "0.05"});
  client::Client client(OptionsFor(server));
  const grpc::Status st = StatusOf([&] { client.ImportFile(SharedData("gltf/cesium_man.gltf"), "cesium_man"); });
  EXPECT_EQ(st.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << st.error_message();
  EXPECT_NE(st.error_message().find("max_image_bytes"), std::string::npos) << st.error_message();
  EXPECT_NE(st.error_message().find("(--max-image-mb)"), std::string::npos) << st.error_message();
  EXPECT_EQ(client.ListMeshes().meshes_size(), 0);
}

}  // namespace
}  // namespace armature::testing
