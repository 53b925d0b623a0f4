// A server-made clip stored as a .glb import: named as asked, its skeleton's
// own clip, and the same after a restart.
#include "server/authoring/derived_clip.h"

#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "../testing/temp_store.h"

namespace armature::server {
namespace {

using test_util::OpenDemoStore;
using test_util::OpenStore;
using test_util::TempDir;

// A store with the demo assets; the clip stored is the demo walk.
class DerivedClipTest : public ::testing::Test {
 protected:
  // The demo walk's keys as the server holds them (its runtime form's, ClipKeysOf), kept for the test.
  const Clip& Walk() {
    if (!walk_) walk_ = test_util::StoredKeys(*store->Snapshot()->FindClip("demo_walk")->part);
    return *walk_;
  }
  std::shared_ptr<const Clip> walk_;
  StatusOr<DerivedClip> Store(const std::string& name, const std::string& skeleton, const Limits& limits = {}) {
    DerivedClipOptions options;
    options.asset_name = name;
    options.skeleton = skeleton;
    return StoreDerivedClip(*store, Walk(), options, limits);
  }

  TempDir dir;
  std::unique_ptr<AssetStore> store = OpenDemoStore(dir.path());
};

TEST_F(DerivedClipTest, AClipForASkeletonIsNamedAsTheAssetAndAnimatesThatSkeleton) {
  const Clip& walk = Walk();
  auto derived = Store("stride", "demo_walk");
  ASSERT_TRUE(derived.ok()) << derived.status().message();
  EXPECT_EQ(derived->asset->record.animates, "demo_walk");
  EXPECT_EQ(derived->asset->record.format, AssetFormat::kGlb);
  EXPECT_EQ(derived->asset->record.filename, "stride.glb");
  ASSERT_NE(derived->clip, nullptr);
  EXPECT_EQ(derived->clip->name, "stride");
  EXPECT_EQ(derived->clip->skeleton_name, "demo_walk");
  EXPECT_EQ(derived->clip->runtime->source_frame_count, walk.frame_count);
  EXPECT_NEAR(derived->clip->runtime->duration, walk.duration, 1e-6);  // float times in glTF
  // Its file's copy of the skeleton is not a skeleton of its own.
  auto reopened = OpenStore(dir.path());
  const auto catalog = reopened->Snapshot();
  EXPECT_EQ(catalog->FindSkeleton("stride").status().code(), StatusCode::kNotFound);
  auto clip = catalog->FindClip("stride");
  ASSERT_TRUE(clip.ok()) << clip.status().message();
  EXPECT_EQ(clip->part->skeleton_name, "demo_walk");
  EXPECT_EQ(clip->part->runtime->source_frame_count, walk.frame_count);
}

TEST_F(DerivedClipTest, WithoutASkeletonTheAssetKeepsItsCopyAndTheClipIsNamedTwice) {
  auto derived = Store("own", "");
  ASSERT_TRUE(derived.ok()) << derived.status().message();
  EXPECT_EQ(derived->clip->name, "own.own");
  EXPECT_EQ(derived->clip->skeleton_name, "own");
  EXPECT_TRUE(store->Snapshot()->FindSkeleton("own").ok());
}

TEST_F(DerivedClipTest, ATakenNameIsAlreadyExistsUnlessReplaceAndABadNameInvalid) {
  auto first = Store("stride", "demo_walk");
  ASSERT_TRUE(first.ok()) << first.status().message();
  EXPECT_EQ(Store("stride", "demo_walk").status().code(), StatusCode::kAlreadyExists);
  DerivedClipOptions options;
  options.asset_name = "stride";
  options.skeleton = "demo_walk";
  options.replace = true;
  auto replaced = StoreDerivedClip(*store, Walk(), options, Limits{});
  ASSERT_TRUE(replaced.ok()) << replaced.status().message();
  EXPECT_NE(replaced->asset->record.file, first->asset->record.file);
  EXPECT_EQ(Store("bad/name", "demo_walk").status().code(), StatusCode::kInvalidArgument);
}

TEST_F(DerivedClipTest, AFileOverMaxUploadMbIsRefusedBeforeItIsWritten) {
  Limits limits;
  limits.max_upload_bytes = 1000;  // the walk's glb takes more
  const Status st = Store("big", "demo_walk", limits).status();
  EXPECT_EQ(st.code(), StatusCode::kResourceExhausted);
  EXPECT_TRUE(st.message().starts_with("the new clip 'big' would be a file over --max-upload-mb (0 MB): "))
      << st.message();
  EXPECT_FALSE(store->Snapshot()->assets.contains("big"));
}

}  // namespace
}  // namespace armature::server
