// Import-time limits: what one file may hold, and the room left under
// --max-assets-mb, each refusal naming its flag.
#include "server/assets/asset_limits.h"

#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "armature/engine/mesh/mesh.h"

namespace armature::server {
namespace {

const AssetContents& DemoCharacter(const Catalog& catalog) { return catalog.assets.at("demo_character")->contents; }

TEST(AssetLimits, AClipOverMaxClipFramesIsRefusedNamingItsFramesAndTheFlag) {
  auto catalog = test_util::DemoCatalog(ClipPrecision{.exact = true});  // limits read the parsed keys
  const AssetContents& contents = DemoCharacter(*catalog);
  const auto frames = static_cast<int64_t>(contents.clips.at(0).clip->frame_count);
  ASSERT_GT(frames, 10);
  Limits limits;
  limits.max_clip_frames = frames;
  EXPECT_TRUE(CheckAssetLimits(contents, limits).ok());
  limits.max_clip_frames = frames - 1;
  const Status st = CheckAssetLimits(contents, limits);
  EXPECT_EQ(st.code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(st.message(), "clip 'demo_character.walk' has " + std::to_string(frames) + " frames, over the limit of " +
                              std::to_string(frames - 1) + " (--max-clip-frames)");
}

TEST(AssetLimits, ATrackWithMoreKeysThanFramesCountsItsKeys) {
  auto clip = std::make_shared<Clip>();
  clip->frame_count = 2;
  clip->joints.resize(1);
  clip->joints[0].rotation.times = {0, 0.1, 0.2, 0.3, 0.4};
  AssetContents contents;
  contents.clips.push_back({"keys", "s", clip});
  Limits limits;
  limits.max_clip_frames = 4;
  EXPECT_EQ(CheckAssetLimits(contents, limits).message(),
            "clip 'keys' has 5 frames, over the limit of 4 (--max-clip-frames)");
}

TEST(AssetLimits, AMeshOverMaxMeshVerticesIsRefusedNamingTheFlag) {
  auto catalog = test_util::DemoCatalog(ClipPrecision{.exact = true});  // limits read the parsed keys
  const AssetContents& contents = DemoCharacter(*catalog);
  const auto vertices = static_cast<int64_t>(contents.meshes.at(0).mesh->vertex_count());
  Limits limits;
  limits.max_mesh_vertices = vertices;
  EXPECT_TRUE(CheckAssetLimits(contents, limits).ok());
  limits.max_mesh_vertices = vertices - 1;
  EXPECT_EQ(CheckAssetLimits(contents, limits).message(), "mesh 'demo_character.body' has " + std::to_string(vertices) +
                                                              " vertices, over the limit of " +
                                                              std::to_string(vertices - 1) + " (--max-mesh-vertices)");
}

TEST(AssetLimits, ImportCapsComeFromTheFlagsNegativeOnesAsZero) {
  Limits limits;
  limits.max_clip_frames = 7;
  limits.max_mesh_vertices = -3;
  limits.max_assets_bytes = 5000;
  limits.max_image_bytes = 600;
  const ImportLimits caps = ImportLimitsOf(limits);
  EXPECT_EQ(caps.max_clip_frames, 7u);
  EXPECT_EQ(caps.max_mesh_vertices, 0u);
  EXPECT_EQ(caps.max_decoded_bytes, 5000u);
  EXPECT_EQ(caps.max_image_bytes, 600u);
  EXPECT_EQ(caps.max_clip_keys, ImportLimits{}.max_clip_keys);  // no flag: the engine's own
  EXPECT_EQ(ImportLimitsWithRoom(limits, 1200).max_decoded_bytes, 3800u);
  EXPECT_EQ(ImportLimitsWithRoom(limits, 9000).max_decoded_bytes, 0u);  // no room, never below 0
}

TEST(AssetLimits, TheTotalIsCheckedInWholeMibRoundedUp) {
  Limits limits;
  limits.max_assets_bytes = 10 << 20;
  EXPECT_TRUE(CheckAssetsTotal(4 << 20, 6 << 20, limits).ok());  // exactly the limit
  const Status st = CheckAssetsTotal((4 << 20) + 1, 6 << 20, limits);
  EXPECT_EQ(st.code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(st.message(),
            "it takes about 5 MiB in memory and the server holds 6 MiB of assets: over the limit of 10 MiB "
            "(--max-assets-mb); delete assets or raise the limit");
}

TEST(AssetLimits, LoadCapsAreNeverBelowTheEngineDefaultsAndRiseWithTheFlags) {
  Limits low;
  low.max_clip_frames = 10;
  low.max_mesh_vertices = 10;
  low.max_assets_bytes = 10;
  low.max_image_bytes = 10;
  const ImportLimits defaults;
  const ImportLimits at_low = LoadLimitsOf(low);
  EXPECT_EQ(at_low.max_clip_frames, defaults.max_clip_frames);
  EXPECT_EQ(at_low.max_mesh_vertices, defaults.max_mesh_vertices);
  EXPECT_EQ(at_low.max_decoded_bytes, defaults.max_decoded_bytes);
  EXPECT_EQ(at_low.max_image_bytes, defaults.max_image_bytes);
  Limits high;
  high.max_clip_frames = 2 * static_cast<int64_t>(defaults.max_clip_frames);
  high.max_image_bytes = 3 * static_cast<int64_t>(defaults.max_image_bytes);
  EXPECT_EQ(LoadLimitsOf(high).max_clip_frames, 2 * defaults.max_clip_frames);
  EXPECT_EQ(LoadLimitsOf(high).max_image_bytes, 3 * defaults.max_image_bytes);
}

TEST(AssetLimits, AnEngineCapsErrorGetsItsFlagAndOthersPassUnchanged) {
  const auto flagged = [](const std::string& message) {
    return WithLimitFlags(Status::ResourceExhausted(message)).status().message();
  };
  EXPECT_EQ(flagged("clip 'a': 12 frames > max_clip_frames = 10"),
            "clip 'a': 12 frames > max_clip_frames = 10 (--max-clip-frames)");
  EXPECT_EQ(flagged("x > max_mesh_vertices = 3"), "x > max_mesh_vertices = 3 (--max-mesh-vertices)");
  EXPECT_EQ(flagged("x > max_image_bytes = 3"), "x > max_image_bytes = 3 (--max-image-mb)");
  EXPECT_EQ(flagged("x > max_decoded_bytes = 3"),
            "x > max_decoded_bytes = 3 (--max-assets-mb, less what the server holds)");
  EXPECT_EQ(flagged("x > max_clip_keys = 3"), "x > max_clip_keys = 3");  // no flag for it
  const Status other = WithLimitFlags(Status::InvalidArgument("max_clip_frames")).status();
  EXPECT_EQ(other.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(other.message(), "max_clip_frames");
}

}  // namespace
}  // namespace armature::server
