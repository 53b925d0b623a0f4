// The assets' memory estimate: what grows it by how much, what is counted
// once however often it is shared, and the /metrics gauges built on it.
#include "server/assets/asset_memory.h"

#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "armature/engine/mesh/mesh.h"

namespace armature::server {
namespace {

std::shared_ptr<Skeleton> TwoJoints() {
  auto s = std::make_shared<Skeleton>();
  s->names = {"root", "tip"};
  s->parents = {-1, 0};
  s->rest.resize(2);
  return s;
}

// A clip of `keys` rotation keys on the root of `skeleton`.
std::shared_ptr<Clip> RotationClip(std::shared_ptr<const Skeleton> skeleton, size_t keys) {
  auto clip = std::make_shared<Clip>();
  clip->skeleton = std::move(skeleton);
  clip->joints.resize(2);
  for (size_t k = 0; k < keys; ++k) {
    clip->joints[0].rotation.times.push_back(static_cast<double>(k));
    clip->joints[0].rotation.values.push_back(Eigen::Quaterniond::Identity());
  }
  return clip;
}

TEST(AssetMemory, EachKeyAddsItsTimeAndItsValue) {
  auto skeleton = TwoJoints();
  AssetContents ten, eleven;
  ten.clips.push_back({"c", "s", RotationClip(skeleton, 10)});
  eleven.clips.push_back({"c", "s", RotationClip(skeleton, 11)});
  EXPECT_EQ(EstimateAssetBytes(eleven) - EstimateAssetBytes(ten), sizeof(double) + sizeof(Eigen::Quaterniond));
}

TEST(AssetMemory, ASkeletonSharedByItsClipsAndListedIsCountedOnce) {
  auto skeleton = TwoJoints();
  AssetContents clip_only, listed_too, two_clips;
  clip_only.clips.push_back({"c", "s", RotationClip(skeleton, 4)});
  listed_too = clip_only;
  listed_too.skeletons.push_back({"s", skeleton});
  EXPECT_EQ(EstimateAssetBytes(listed_too), EstimateAssetBytes(clip_only));
  two_clips = clip_only;
  two_clips.clips.push_back({"d", "s", RotationClip(skeleton, 4)});
  const size_t one_clip = EstimateAssetBytes(two_clips) - EstimateAssetBytes(clip_only);
  // The second clip adds its tracks only: the first clip's total less the skeleton.
  AssetContents skeleton_only;
  skeleton_only.skeletons.push_back({"s", skeleton});
  EXPECT_EQ(one_clip, EstimateAssetBytes(clip_only) - EstimateAssetBytes(skeleton_only));
  // A longer joint name adds its characters.
  auto renamed = TwoJoints();
  renamed->names[1] = "tip_of_it";
  AssetContents longer;
  longer.skeletons.push_back({"s", renamed});
  EXPECT_EQ(EstimateAssetBytes(longer) - EstimateAssetBytes(skeleton_only), 6u);
}

TEST(AssetMemory, AMaterialAndItsImageSharedByTwoMeshesAreCountedOnce) {
  auto image = std::make_shared<MaterialImage>(MaterialImage{"img", "image/png", std::string(1000, 'x')});
  auto material = std::make_shared<Material>();
  material->images = {image};
  auto mesh_a = std::make_shared<Mesh>();
  mesh_a->materials = {material};
  auto mesh_b = std::make_shared<Mesh>(*mesh_a);
  AssetContents one, two;
  one.meshes.push_back({"a", "", mesh_a});
  two = one;
  two.meshes.push_back({"b", "", mesh_b});
  AssetContents bare_two;
  bare_two.meshes.push_back({"a", "", std::make_shared<Mesh>()});
  bare_two.meshes.push_back({"b", "", std::make_shared<Mesh>()});
  AssetContents bare_one;
  bare_one.meshes.push_back({"a", "", std::make_shared<Mesh>()});
  // The second mesh adds only its own struct (plus its one material pointer).
  EXPECT_EQ(EstimateAssetBytes(two) - EstimateAssetBytes(one),
            EstimateAssetBytes(bare_two) - EstimateAssetBytes(bare_one) + sizeof(std::shared_ptr<const Material>));
  // The image's stored bytes are counted: 1000 more bytes, 1000 more.
  auto big = std::make_shared<MaterialImage>(*image);
  big->bytes += std::string(1000, 'y');
  auto big_material = std::make_shared<Material>(*material);
  big_material->images = {big};
  auto big_mesh = std::make_shared<Mesh>(*mesh_a);
  big_mesh->materials = {big_material};
  AssetContents bigger;
  bigger.meshes.push_back({"a", "", big_mesh});
  EXPECT_EQ(EstimateAssetBytes(bigger) - EstimateAssetBytes(one), 1000u);
}

TEST(AssetMemory, HeldBytesSumTheAssetsButTheOneReplaced) {
  auto catalog = test_util::DemoCatalog();
  const StoredAsset& walk = *catalog->assets.at("demo_walk");
  const StoredAsset& character = *catalog->assets.at("demo_character");
  const size_t w = EstimateAssetBytes(walk.contents), c = EstimateAssetBytes(character.contents);
  EXPECT_GT(w, 0u);
  EXPECT_GT(c, w);  // a mesh besides a clip of the same skeleton
  EXPECT_EQ(HeldAssetBytes(*catalog), w + c);
  EXPECT_EQ(HeldAssetBytes(*catalog, &walk), c);
  EXPECT_EQ(HeldAssetBytes(*catalog, &character), w);
}

TEST(AssetMemory, MetricsCountThePartsAndTheBytes) {
  auto catalog = test_util::DemoCatalog();
  PrometheusText out;
  CollectAssetMetrics(*catalog, out);
  const std::string& text = out.text();
  for (const char* line : {"armature_assets_loaded{kind=\"asset\"} 2\n",
                           "armature_assets_loaded{kind=\"skeleton\"} 2\n", "armature_assets_loaded{kind=\"clip\"} 2\n",
                           "armature_assets_loaded{kind=\"mesh\"} 1\n", "# TYPE armature_assets_memory_bytes gauge\n"})
    EXPECT_NE(text.find(line), std::string::npos) << line << " in\n" << text;
  const std::string memory = "\narmature_assets_memory_bytes ";
  const size_t at = text.find(memory);
  ASSERT_NE(at, std::string::npos) << text;
  EXPECT_EQ(std::stod(text.substr(at + memory.size())), static_cast<double>(HeldAssetBytes(*catalog)));
  // The in-memory catalog has no stored files: 0 source bytes.
  EXPECT_NE(text.find("armature_assets_source_bytes 0\n"), std::string::npos) << text;
}

}  // namespace
}  // namespace armature::server
