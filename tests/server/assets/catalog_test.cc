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
  EXPECT_EQ(mesh->part->skeleton, "demo_character");
  auto clip = catalog->FindClip("demo_walk");
  ASSERT_TRUE(clip.ok());
  EXPECT_EQ(clip->part->skeleton, "demo_walk");
  EXPECT_EQ(clip->part->clip->skeleton->size(), 19u);
  EXPECT_TRUE(catalog->FindSkeleton("demo_character").ok());
}

TEST(Catalog, AnUnknownNameIsNotFoundNamingTheKind) {
  auto catalog = DemoCatalog();
  auto mesh = catalog->FindMesh("demo_character");
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.status().code(), StatusCode::kNotFound);
  EXPECT_EQ(mesh.status().message(), "mesh 'demo_character' not found");
  EXPECT_EQ(catalog->FindClip("nope").status().message(), "clip 'nope' not found");
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
