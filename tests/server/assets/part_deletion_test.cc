// Deleting by a part's name is refused when it would drop other parts of the same asset.
#include "server/assets/part_deletion.h"

#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"

namespace armature::server {
namespace {

// An asset laid out like Khronos' Fox: three clips, one mesh, one skeleton (names only).
StoredAsset FoxLike() {
  StoredAsset fox;
  fox.record.name = "fox";
  for (const char* clip : {"fox.Survey", "fox.Walk", "fox.Run"}) fox.contents.clips.push_back({clip, "fox", nullptr});
  fox.contents.meshes.push_back({"fox.fox", "fox", nullptr});
  fox.contents.skeletons.push_back({"fox", nullptr});
  return fox;
}

TEST(PartDeletion, AClipOfALargerAssetIsRefusedNamingWhatElseItHolds) {
  const Status st = CheckDeletionTakesOnly(FoxLike(), "fox.Walk");
  EXPECT_EQ(st.code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(st.message(),
            "clip 'fox.Walk' belongs to asset 'fox', which also holds 2 clips, 1 mesh and 1 skeleton; "
            "delete the asset 'fox' to remove them all");
  EXPECT_EQ(CheckDeletionTakesOnly(FoxLike(), "fox.fox").message(),
            "mesh 'fox.fox' belongs to asset 'fox', which also holds 3 clips and 1 skeleton; "
            "delete the asset 'fox' to remove them all");
}

TEST(PartDeletion, TheAssetItselfOrItsOnlyPartIsDeletable) {
  EXPECT_TRUE(CheckDeletionTakesOnly(FoxLike(), "fox").ok());
  StoredAsset solo;
  solo.record.name = "solo";
  solo.contents.clips.push_back({"solo.Take", "", nullptr});
  EXPECT_TRUE(CheckDeletionTakesOnly(solo, "solo.Take").ok());
  // A BVH: the clip and its skeleton carry the asset's name.
  auto catalog = test_util::DemoCatalog();
  EXPECT_TRUE(CheckDeletionTakesOnly(*catalog->assets.at("demo_walk"), "demo_walk").ok());
  EXPECT_EQ(CheckDeletionTakesOnly(*catalog->assets.at("demo_character"), "demo_character.walk").message(),
            "clip 'demo_character.walk' belongs to asset 'demo_character', which also holds 1 mesh and "
            "1 skeleton; delete the asset 'demo_character' to remove them all");
}

}  // namespace
}  // namespace armature::server
