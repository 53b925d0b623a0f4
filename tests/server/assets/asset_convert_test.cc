// Stored assets → their API listings: every number is the parsed part's own.
#include "server/assets/asset_convert.h"

#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "armature/engine/io/demo_walk.h"
#include "armature/engine/mesh/mesh.h"

namespace armature::server {
namespace {

TEST(AssetConvert, AnAssetListsEachOfItsPartsWithTheirOwnNumbers) {
  auto catalog = test_util::DemoCatalog();
  const StoredAsset& asset = *catalog->assets.at("demo_character");
  const v1::AssetInfo info = AssetInfoOf(asset);
  EXPECT_EQ(info.name(), "demo_character");
  EXPECT_EQ(info.format(), "glb");
  ASSERT_EQ(info.skeletons_size(), 1);
  ASSERT_EQ(info.clips_size(), 1);
  ASSERT_EQ(info.meshes_size(), 1);
  const NamedSkeleton& skeleton = asset.contents.skeletons[0];
  EXPECT_EQ(info.skeletons(0).name(), "demo_character");
  EXPECT_EQ(info.skeletons(0).asset(), "demo_character");
  EXPECT_EQ(info.skeletons(0).joint_count(), static_cast<int>(skeleton.skeleton->size()));
  EXPECT_EQ(info.clips(0).name(), "demo_character.walk");
  EXPECT_EQ(info.clips(0).joints_size(), 0);  // listings leave the joints out
  EXPECT_EQ(info.meshes(0).name(), "demo_character.body");
}

TEST(AssetConvert, AClipInfoCarriesItsTimingAndOnRequestItsJoints) {
  auto catalog = test_util::DemoCatalog();
  const auto ref = *catalog->FindClip("demo_walk");
  const CompressedClip& clip = *ref.part->runtime;
  const v1::ClipInfo info = ClipInfoOf(*ref.asset, *ref.part, true);
  EXPECT_EQ(info.skeleton(), "demo_walk");
  EXPECT_EQ(info.asset(), "demo_walk");
  EXPECT_EQ(info.frames(), static_cast<int>(clip.source_frame_count));
  EXPECT_DOUBLE_EQ(info.frame_time(), clip.source_frame_time);
  EXPECT_DOUBLE_EQ(info.duration(), clip.duration);
  // The demo walk: 3 cycles of 1 s at 30 fps, first and last frame included.
  EXPECT_EQ(info.frames(), kDemoWalkCycles * 30 + 1);
  ASSERT_EQ(info.joints_size(), static_cast<int>(clip.skeleton->size()));
  for (int j = 0; j < info.joints_size(); ++j) EXPECT_EQ(info.joints(j), clip.skeleton->names[j]);
  EXPECT_EQ(info.joints(0), "Hips");
}

TEST(AssetConvert, AMeshInfoCountsItsVerticesTrianglesAndInfluences) {
  auto catalog = test_util::DemoCatalog();
  const auto ref = *catalog->FindMesh("demo_character.body");
  const Mesh& mesh = *ref.part->mesh;
  const v1::MeshInfo info = MeshInfoOf(*ref.asset, *ref.part);
  EXPECT_EQ(info.skeleton(), "demo_character");
  EXPECT_EQ(info.vertex_count(), static_cast<int>(mesh.positions.size()));
  EXPECT_EQ(info.triangle_count() * 3, static_cast<int>(mesh.triangles.size()));
  // The most influences of any vertex, counted from the skin's offsets.
  uint32_t most = 0;
  for (size_t v = 0; v + 1 < mesh.influence_offsets.size(); ++v)
    most = std::max(most, mesh.influence_offsets[v + 1] - mesh.influence_offsets[v]);
  EXPECT_EQ(info.max_influences(), static_cast<int>(most));
  EXPECT_GE(most, 2u);
  EXPECT_EQ(info.target_names_size(), 0);
  // A mesh part without its mesh (names only) lists its names and no counts.
  const v1::MeshInfo bare = MeshInfoOf(*ref.asset, NamedMesh{"bare", "", nullptr});
  EXPECT_EQ(bare.name(), "bare");
  EXPECT_EQ(bare.vertex_count(), 0);
}

}  // namespace
}  // namespace armature::server
