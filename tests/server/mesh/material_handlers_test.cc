// GetMaterial and GetMaterialImage over a catalog holding a mesh with two
// materials that share an image: every field is the material's own.
#include "server/mesh/material_handlers.h"

#include <gtest/gtest.h>

#include "armature/engine/mesh/material.h"
#include "armature/engine/mesh/mesh.h"

namespace armature::server {
namespace {

constexpr char kPng[] = "\x89PNG\r\n\x1a\n-not-decoded";

std::shared_ptr<const Catalog> PaintedCatalog() {
  auto albedo =
      std::make_shared<MaterialImage>(MaterialImage{"albedo", "image/png", std::string(kPng, sizeof kPng - 1)});
  auto normals = std::make_shared<MaterialImage>(MaterialImage{"normals", "image/jpeg", std::string(300, 'n')});
  auto skin = std::make_shared<Material>();
  skin->name = "skin";
  skin->base_color_factor = {0.8, 0.6, 0.5, 1};
  skin->metallic_factor = 0;
  skin->roughness_factor = 0.7;
  skin->emissive_factor = {0.1, 0, 0};
  skin->alpha_mode = "MASK";
  skin->alpha_cutoff = 0.3;
  skin->double_sided = true;
  skin->images = {albedo, normals};
  skin->base_color_texture.image = 0;
  skin->base_color_texture.sampler.mag_filter = 9729;
  skin->normal_texture.image = 1;
  skin->normal_texture.scale = 0.5;
  skin->normal_texture.texcoord = 0;
  auto plain = std::make_shared<Material>();
  plain->name = "plain";
  auto mesh = std::make_shared<Mesh>();
  mesh->materials = {skin, plain};
  auto asset = std::make_shared<StoredAsset>();
  asset->record.name = "painted";
  asset->contents.meshes.push_back({"painted.body", "", mesh});
  auto catalog = BuildCatalog({{"painted", asset}});
  EXPECT_TRUE(catalog.ok()) << catalog.status().message();
  return std::move(*catalog);
}

v1::GetMaterialRequest MaterialRequest(int index) {
  v1::GetMaterialRequest request;
  request.set_mesh("painted.body");
  request.set_material(index);
  return request;
}

TEST(MaterialHandlers, AMaterialCarriesItsFactorsTexturesAndImageSizes) {
  auto catalog = PaintedCatalog();
  v1::Material m;
  ASSERT_TRUE(GetMaterial(*catalog, MaterialRequest(0), &m).ok());
  EXPECT_EQ(m.mesh(), "painted.body");
  EXPECT_EQ(m.index(), 0);
  EXPECT_EQ(m.name(), "skin");
  ASSERT_EQ(m.base_color_factor_size(), 4);
  EXPECT_EQ(m.base_color_factor(1), 0.6);
  EXPECT_EQ(m.roughness_factor(), 0.7);
  ASSERT_EQ(m.emissive_factor_size(), 3);
  EXPECT_EQ(m.emissive_factor(0), 0.1);
  EXPECT_EQ(m.alpha_mode(), "MASK");
  EXPECT_EQ(m.alpha_cutoff(), 0.3);
  EXPECT_TRUE(m.double_sided());
  ASSERT_TRUE(m.has_base_color_texture());
  EXPECT_EQ(m.base_color_texture().image(), 0);
  EXPECT_EQ(m.base_color_texture().sampler().mag_filter(), 9729);
  EXPECT_EQ(m.base_color_texture().sampler().wrap_s(), 10497);
  ASSERT_TRUE(m.has_normal_texture());
  EXPECT_EQ(m.normal_texture().image(), 1);
  EXPECT_EQ(m.normal_texture().scale(), 0.5);
  // Slots without a texture stay unset.
  EXPECT_FALSE(m.has_occlusion_texture());
  EXPECT_FALSE(m.has_emissive_texture());
  EXPECT_FALSE(m.has_metallic_roughness_texture());
  ASSERT_EQ(m.images_size(), 2);
  EXPECT_EQ(m.images(0).name(), "albedo");
  EXPECT_EQ(m.images(0).mime_type(), "image/png");
  EXPECT_EQ(m.images(0).byte_size(), static_cast<int64_t>(sizeof kPng - 1));
  EXPECT_EQ(m.images(1).index(), 1);
  EXPECT_EQ(m.images(1).byte_size(), 300);

  v1::Material plain;
  ASSERT_TRUE(GetMaterial(*catalog, MaterialRequest(1), &plain).ok());
  EXPECT_EQ(plain.name(), "plain");
  EXPECT_EQ(plain.metallic_factor(), 1);  // glTF's default
  EXPECT_EQ(plain.images_size(), 0);
}

TEST(MaterialHandlers, AMaterialOutOfRangeIsRefusedNamingTheCount) {
  auto catalog = PaintedCatalog();
  v1::Material m;
  for (int index : {2, -1}) {
    const Status st = GetMaterial(*catalog, MaterialRequest(index), &m);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(st.message(),
              "material: " + std::to_string(index) + " is out of range (mesh 'painted.body' has 2 materials)");
  }
  v1::GetMaterialRequest unknown = MaterialRequest(0);
  unknown.set_mesh("painted.head");
  const Status st = GetMaterial(*catalog, unknown, &m);
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_TRUE(st.message().starts_with("mesh: ")) << st.message();
}

TEST(MaterialHandlers, AnImageIsItsStoredBytesWithinTheReplyLimit) {
  auto catalog = PaintedCatalog();
  v1::GetMaterialImageRequest request;
  request.set_mesh("painted.body");
  request.set_material(0);
  request.set_image(0);
  v1::MaterialImage image;
  ASSERT_TRUE(GetMaterialImage(*catalog, request, &image, Limits{}).ok());
  EXPECT_EQ(image.data(), std::string(kPng, sizeof kPng - 1));
  EXPECT_EQ(image.mime_type(), "image/png");
  EXPECT_EQ(image.name(), "albedo");
  EXPECT_EQ(image.mesh(), "painted.body");
  EXPECT_EQ(image.image(), 0);

  request.set_image(1);
  Limits limits;
  limits.max_message_bytes = 300;  // exactly the image
  EXPECT_TRUE(GetMaterialImage(*catalog, request, &image, limits).ok());
  EXPECT_EQ(image.data().size(), 300u);
  limits.max_message_bytes = 299;
  const Status big = GetMaterialImage(*catalog, request, &image, limits);
  EXPECT_EQ(big.code(), StatusCode::kResourceExhausted);
  EXPECT_NE(big.message().find("an image of 300 bytes"), std::string::npos) << big.message();
  EXPECT_NE(big.message().find("--max-message-mb"), std::string::npos) << big.message();

  request.set_image(2);
  EXPECT_EQ(GetMaterialImage(*catalog, request, &image, Limits{}).message(),
            "image: 2 is out of range (material 0 of mesh 'painted.body' has 2 images)");
  request.set_material(1);
  request.set_image(0);
  EXPECT_EQ(GetMaterialImage(*catalog, request, &image, Limits{}).message(),
            "image: 0 is out of range (material 1 of mesh 'painted.body' has 0 images)");
}

}  // namespace
}  // namespace armature::server
