// CreateClip's bake: a motion sampled at k / fps into keys that equal the
// clip sampled by the engine at those times, within the flags' budgets.
#include "server/authoring/clip_bake.h"

#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "server/authoring/create_clip_validation.h"

namespace armature::server {
namespace {

v1::ClipBake BakeOf(const std::string& clip, double fps, double duration) {
  v1::ClipBake bake;
  bake.mutable_motion()->add_layers()->set_clip(clip);
  bake.set_fps(fps);
  bake.set_duration(duration);
  return bake;
}

TEST(ClipBake, KeysAreTheClipSampledAtEachFrameAndAtTheEnd) {
  auto catalog = test_util::DemoCatalog();
  auto baked = BakeMotion(*catalog, Limits{}, BakeOf("demo_walk", 10, 0.25));
  ASSERT_TRUE(baked.ok()) << baked.status().message();
  EXPECT_EQ(baked->skeleton, "demo_walk");
  // The source as the server samples it: its runtime form, through the sampling job.
  const CompressedClip& source = *catalog->FindClip("demo_walk")->part->runtime;
  EXPECT_EQ(baked->clip.skeleton, source.skeleton);
  // 0, 0.1, 0.2 at 10 fps, then the duration itself: as 32-bit floats.
  const std::vector<double> times = {0, StoredKeyTime(0.1), StoredKeyTime(0.2), 0.25};
  EXPECT_EQ(baked->clip.frame_count, times.size());
  EXPECT_EQ(baked->clip.duration, 0.25);
  ASSERT_EQ(baked->clip.joints.size(), source.skeleton->size());
  std::vector<Trs> pose(source.skeleton->size());
  for (size_t k = 0; k < times.size(); ++k) {
    ASSERT_TRUE((ClipSamplingJob{&source, times[k], WrapMode::kClamp, nullptr, pose, {}}.Run().ok()));
    for (size_t j = 0; j < pose.size(); ++j) {
      const JointTrack& t = baked->clip.joints[j];
      ASSERT_EQ(t.rotation.times, times);
      EXPECT_NEAR(std::abs(t.rotation.values[k].dot(pose[j].rotation)), 1.0, 1e-9) << "joint " << j << " key " << k;
      EXPECT_LT((t.translation.values[k] - pose[j].translation).norm(), 1e-9) << "joint " << j << " key " << k;
    }
  }
  // The BVH has no scale: no joint is scaled, so no scale tracks are kept.
  for (const JointTrack& t : baked->clip.joints) EXPECT_TRUE(t.scale.empty());
}

TEST(ClipBake, FpsDefaultsTo30) {
  auto catalog = test_util::DemoCatalog();
  auto baked = BakeMotion(*catalog, Limits{}, BakeOf("demo_walk", 0, 1.0));
  ASSERT_TRUE(baked.ok()) << baked.status().message();
  EXPECT_EQ(baked->clip.frame_count, 31u);  // 0, 1/30, …, 30/30
}

TEST(ClipBake, BadFpsDurationOrMotionNameTheirField) {
  auto catalog = test_util::DemoCatalog();
  const Status fps = BakeMotion(*catalog, Limits{}, BakeOf("demo_walk", 1001, 1)).status();
  EXPECT_EQ(fps.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(fps.message(), "bake.fps: 1001.000000 is not in (0, 1000]");
  EXPECT_EQ(BakeMotion(*catalog, Limits{}, BakeOf("demo_walk", 30, 0)).status().message(),
            "bake.duration: required, a finite number of seconds > 0");
  v1::ClipBake no_layers = BakeOf("demo_walk", 30, 1);
  no_layers.mutable_motion()->clear_layers();
  EXPECT_EQ(BakeMotion(*catalog, Limits{}, no_layers).status().message(),
            "bake.motion: required (give at least one layer)");
  const Status unknown = BakeMotion(*catalog, Limits{}, BakeOf("Wave", 30, 1)).status();
  EXPECT_EQ(unknown.code(), StatusCode::kNotFound);
  EXPECT_TRUE(unknown.message().starts_with("bake.motion.layers[0]: ")) << unknown.message();
}

TEST(ClipBake, MoreKeysThanMaxClipFramesAreRefusedBeforeSampling) {
  auto catalog = test_util::DemoCatalog();
  Limits limits;
  limits.max_clip_frames = 4;  // 0, 0.1, 0.2 and the end: 4 keys fit
  EXPECT_TRUE(BakeMotion(*catalog, limits, BakeOf("demo_walk", 10, 0.25)).ok());
  limits.max_clip_frames = 3;
  const Status st = BakeMotion(*catalog, limits, BakeOf("demo_walk", 10, 0.25)).status();
  EXPECT_EQ(st.code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(st.message(), "bake: 0.250000 s at 10.000000 fps is 3+ keys, over the limit of 3 (--max-clip-frames)");
}

TEST(ClipBake, AClipLargerInMemoryThanMaxUploadMbIsRefused) {
  auto catalog = test_util::DemoCatalog();
  const int64_t joints = static_cast<int64_t>(catalog->FindSkeleton("demo_walk")->part->skeleton->size());
  // 1 s at 30 fps: 30 whole frames, counted as 30 + 2 keys per joint.
  const int64_t bytes = (30 + 2) * joints * kBakeBytesPerJointKey;
  Limits limits;
  limits.max_upload_bytes = bytes;
  EXPECT_TRUE(BakeMotion(*catalog, limits, BakeOf("demo_walk", 30, 1)).ok());
  limits.max_upload_bytes = bytes - 1;
  const Status st = BakeMotion(*catalog, limits, BakeOf("demo_walk", 30, 1)).status();
  EXPECT_EQ(st.code(), StatusCode::kResourceExhausted);
  EXPECT_NE(st.message().find("31 keys × " + std::to_string(joints) + " joints"), std::string::npos) << st.message();
  EXPECT_NE(st.message().find("--max-upload-mb"), std::string::npos) << st.message();
}

}  // namespace
}  // namespace armature::server
