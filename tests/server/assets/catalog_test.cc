// The catalog's lookups and indexes, over assets parsed in memory.
#include "server/assets/catalog.h"

#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"

namespace armature::server {
namespace {

using test_util::DemoCatalog;
using test_util::ParsedAsset;

TEST(Catalog, FindsEachPartKindByItsFullName) {
  auto catalog = DemoCatalog();
  auto mesh = catalog->FindMesh("demo_character.body");
  ASSERT_TRUE(mesh.ok()) << mesh.status().message();
  EXPECT_EQ(mesh->asset->record.name, "demo_character");
  EXPECT_EQ(mesh->part->skeleton_name, "demo_character");
  auto clip = catalog->FindClip("demo_walk");
  ASSERT_TRUE(clip.ok());
  EXPECT_EQ(clip->part->skeleton_name, "demo_walk");
  EXPECT_EQ(clip->part->runtime->skeleton->size(), 19u);
  EXPECT_TRUE(catalog->FindSkeleton("demo_character").ok());
}

TEST(Catalog, AnUnknownNameIsNotFoundNamingTheKind) {
  auto catalog = DemoCatalog();
  auto mesh = catalog->FindMesh("demo_character");
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.status().code(), StatusCode::kNotFound);
  // An asset's name where a part's is wanted: the asset's parts of that kind are listed.
  EXPECT_EQ(mesh.status().message(),
            "mesh 'demo_character' not found; asset 'demo_character' has meshes: "
            "demo_character.body");
  EXPECT_EQ(catalog->FindMesh("demo_walk").status().message(),
            "mesh 'demo_walk' not found; asset 'demo_walk' has no meshes");
  EXPECT_EQ(catalog->FindClip("demo_character").status().message(),
            "clip 'demo_character' not found; asset 'demo_character' has clips: demo_character.walk");
  EXPECT_EQ(catalog->FindClip("nope").status().message(), "clip 'nope' not found");
}

TEST(Catalog, ANearMissSuggestsTheClosestName) {
  auto catalog = DemoCatalog();
  EXPECT_EQ(catalog->FindClip("demo_wlak").status().message(), "clip 'demo_wlak' not found; did you mean 'demo_walk'?");
  EXPECT_EQ(catalog->FindClip("Demo_Walk").status().message(), "clip 'Demo_Walk' not found; did you mean 'demo_walk'?");
  EXPECT_EQ(catalog->FindMesh("demo_character.bdy").status().message(),
            "mesh 'demo_character.bdy' not found; did you mean 'demo_character.body'?");
  EXPECT_EQ(catalog->FindSkeleton("demo_charactr").status().message(),
            "skeleton 'demo_charactr' not found; did you mean 'demo_character'?");
}

TEST(Catalog, FindOwnerResolvesAnAssetOrAnyOfItsParts) {
  auto catalog = DemoCatalog();
  for (const char* name : {"demo_character", "demo_character.body", "demo_character.walk"}) {
    auto owner = catalog->FindOwner(name);
    ASSERT_TRUE(owner.ok()) << name;
    EXPECT_EQ((*owner)->record.name, "demo_character") << name;
  }
  EXPECT_EQ(catalog->FindOwner("x").status().code(), StatusCode::kNotFound);
}

TEST(Catalog, TwoAssetsClaimingOnePartNameAreRefusedNamingBoth) {
  const std::string bvh = WriteBvh(*MakeDemoWalk().clip);
  std::map<std::string, std::shared_ptr<const StoredAsset>> assets;
  assets["a"] = ParsedAsset("walk", AssetFormat::kBvh, bvh);  // parts named "walk"
  assets["b"] = ParsedAsset("walk", AssetFormat::kBvh, bvh);
  auto catalog = BuildCatalog(std::move(assets));
  ASSERT_FALSE(catalog.ok());
  EXPECT_EQ(catalog.status().code(), StatusCode::kAlreadyExists);
  EXPECT_NE(catalog.status().message().find("clip 'walk' already exists"), std::string::npos)
      << catalog.status().message();
}

}  // namespace
}  // namespace armature::server
