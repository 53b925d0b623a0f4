// Morph weights in the compressed runtime form (issue 30), on the real
// files of ../shared/data: every frame's weight within the stated weight
// bound against the stored track, the sizes they come to, `exact` bit for
// bit, and the keys export reads back.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/compression/clip_keys.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/anim/compression/compressed_weights.h"
#include "../../testing/shared_clips.h"

namespace armature {
namespace {

const std::vector<test_util::SharedClip>& Clips() {
  static const std::vector<test_util::SharedClip> clips = test_util::LoadSharedClips();
  return clips;
}

#define SKIP_WITHOUT_SHARED_DATA() \
  if (Clips().empty()) GTEST_SKIP() << "../shared/data is absent: no real clips to compress"

const test_util::SharedClip* Named(const std::string& name) {
  for (const test_util::SharedClip& c : Clips())
    if (c.name == name) return &c;
  return nullptr;
}

// The largest weight error of `z` against the stored weights at every frame.
double WorstWeightError(const Clip& source, const CompressedClip& z) {
  double worst = 0;
  for (const WeightsTrack& track : source.weights) {
    std::vector<double> expected(track.targets), actual(track.targets);
    for (size_t f = 0; f < z.frames.count; ++f) {
      const double t = z.frames.Time(f);
      SampleWeights(track, t, {std::nullopt, WrapMode::kClamp}, expected);
      EXPECT_TRUE(z.SampleMorphWeights(track.mesh, track.targets, t, std::nullopt, actual)) << track.mesh;
      for (size_t k = 0; k < track.targets; ++k) worst = std::max(worst, std::abs(actual[k] - expected[k]));
    }
  }
  return worst;
}

TEST(MorphWeightsCompression, EveryFrameIsWithinTheWeightBoundOnEveryClip) {
  SKIP_WITHOUT_SHARED_DATA();
  size_t with_weights = 0, grew = 0;
  for (const test_util::SharedClip& c : Clips()) {
    if (c.clip->weights.empty()) continue;
    ++with_weights;
    StatusOr<std::shared_ptr<const CompressedClip>> z = CompressClip(c.clip);
    ASSERT_TRUE(z.ok()) << c.name;
    ASSERT_FALSE((*z)->exact()) << c.name << ": " << (*z)->warning;
    ASSERT_EQ((*z)->weights.size(), c.clip->weights.size()) << c.name;
    const double bound = WeightBound((*z)->bound), worst = WorstWeightError(*c.clip, **z);
    EXPECT_NEAR(bound, 0.01 / 3, 1e-12) << c.name << ": the default bound over its shell distance";
    EXPECT_LE(worst, bound) << c.name;
    EXPECT_NEAR((*z)->weight_error, worst, 1e-6) << c.name << ": the error the compressor reports is the one measured";
    // A tighter bound holds too, at no fewer bytes (more where the weights move).
    StatusOr<std::shared_ptr<const CompressedClip>> tight = CompressClip(c.clip, ClipPrecision{false, 0.001});
    ASSERT_TRUE(tight.ok()) << c.name;
    if ((*tight)->exact()) continue;  // the joints could not meet it
    EXPECT_LE(WorstWeightError(*c.clip, **tight), WeightBound((*tight)->bound)) << c.name;
    size_t bytes = 0, tight_bytes = 0;
    for (const CompressedWeights& w : (*z)->weights) bytes += w.ByteSize();
    for (const CompressedWeights& w : (*tight)->weights) tight_bytes += w.ByteSize();
    EXPECT_GE(tight_bytes, bytes) << c.name;
    if (tight_bytes > bytes) ++grew;
  }
  EXPECT_GE(grew, 1u) << "AnimatedMorphCube's weights move: a tighter bound takes more bits";
  EXPECT_GE(with_weights, 2u) << "AnimatedMorphCube, SimpleMorph and RobotExpressive have morph weights";
}

// AnimatedMorphCube was 24.3 bytes per joint-sample with its weights kept as
// doubles; RobotExpressive's clips carry three faces' weights each.
TEST(MorphWeightsCompression, ClipsWithMorphWeightsComeToFewBytes) {
  SKIP_WITHOUT_SHARED_DATA();
  const test_util::SharedClip* cube = Named("gltf/AnimatedMorphCube/AnimatedMorphCube.gltf#AnimatedMorphCube.Square");
  const test_util::SharedClip* idle = Named("gltf/RobotExpressive/RobotExpressive.glb#RobotExpressive.Idle");
  if (!cube || !idle) GTEST_SKIP() << "AnimatedMorphCube or RobotExpressive absent";
  StatusOr<std::shared_ptr<const CompressedClip>> zc = CompressClip(cube->clip), zi = CompressClip(idle->clip);
  ASSERT_TRUE(zc.ok() && zi.ok());
  EXPECT_LT((*zc)->BytesPerJointSample(), 2.0);
  // Its one joint does not move: no segments are kept for it.
  EXPECT_TRUE((*zc)->animated.empty());
  EXPECT_TRUE((*zc)->segment_offsets.empty() && (*zc)->data.empty());
  EXPECT_LT((*zi)->BytesPerJointSample(), 0.2);
}

TEST(MorphWeightsCompression, ExactKeepsTheStoredWeightsBitForBit) {
  SKIP_WITHOUT_SHARED_DATA();
  const test_util::SharedClip* cube = Named("gltf/AnimatedMorphCube/AnimatedMorphCube.gltf#AnimatedMorphCube.Square");
  if (!cube) GTEST_SKIP() << "AnimatedMorphCube absent";
  StatusOr<std::shared_ptr<const CompressedClip>> z = CompressClip(cube->clip, ClipPrecision{true, 0.01});
  ASSERT_TRUE(z.ok() && (*z)->exact());
  const WeightsTrack& track = cube->clip->weights[0];
  std::vector<double> expected(track.targets), actual(track.targets);
  for (double t = 0; t <= cube->clip->duration; t += cube->clip->duration / 301) {
    SampleWeights(track, t, {std::nullopt, WrapMode::kClamp}, expected);
    ASSERT_TRUE((*z)->SampleMorphWeights(track.mesh, track.targets, t, std::nullopt, actual));
    EXPECT_EQ(std::memcmp(expected.data(), actual.data(), expected.size() * sizeof(double)), 0) << t;
  }
  EXPECT_FALSE((*z)->SampleMorphWeights("no such mesh", track.targets, 0, std::nullopt, actual));
}

// A hand-made ramp then hold: interpolated between kept samples, STEP holds
// the frame at or before the time, and the keys export reads are the frames.
TEST(MorphWeightsCompression, RampAndHoldSampleAsInterpolatedFramesAndExportAsKeys) {
  auto skeleton = std::make_shared<Skeleton>();
  skeleton->names = {"root"};
  skeleton->parents = {-1};
  skeleton->rest.resize(1);
  skeleton->end_sites.resize(1);
  auto clip = std::make_shared<Clip>();
  clip->skeleton = skeleton;
  clip->joints.resize(1);
  clip->weights.push_back({"face", 2, {0, 1, 2}, {0, 1, 1, 0.25, 1, 0.25}, Interpolation::kLinear});
  clip->duration = 2;
  clip->frame_count = 3;
  StatusOr<std::shared_ptr<const CompressedClip>> z = CompressClip(clip);
  ASSERT_TRUE(z.ok()) << z.status().message();
  ASSERT_FALSE((*z)->exact()) << (*z)->warning;
  const double bound = WeightBound((*z)->bound);
  std::vector<double> w(2);
  ASSERT_TRUE((*z)->SampleMorphWeights("face", 2, 0.5, std::nullopt, w));
  EXPECT_NEAR(w[0], 0.5, bound);  // on the ramp
  EXPECT_NEAR(w[1], 0.625, bound);
  ASSERT_TRUE((*z)->SampleMorphWeights("face", 2, 1.5, std::nullopt, w));
  EXPECT_NEAR(w[0], 1, bound);  // held
  EXPECT_NEAR(w[1], 0.25, bound);
  const double frame = (*z)->frames.frame_time;
  ASSERT_TRUE((*z)->SampleMorphWeights("face", 2, 2.5 * frame, Interpolation::kStep, w));
  EXPECT_NEAR(w[0], 2 * frame, bound);  // frame 2's weight
  StatusOr<std::shared_ptr<const Clip>> keys = ClipKeysOf(**z);
  ASSERT_TRUE(keys.ok());
  ASSERT_EQ((*keys)->weights.size(), 1u);
  const WeightsTrack& back = (*keys)->weights[0];
  EXPECT_EQ(back.times.size(), (*z)->frames.count);
  EXPECT_EQ(back.times.back(), 2.0);
  std::vector<double> expected(2);
  for (size_t f = 0; f < back.times.size(); ++f) {
    SampleWeights(clip->weights[0], back.times[f], {std::nullopt, WrapMode::kClamp}, expected);
    EXPECT_NEAR(back.values[2 * f], expected[0], bound) << f;
    EXPECT_NEAR(back.values[2 * f + 1], expected[1], bound) << f;
  }
}

}  // namespace
}  // namespace armature
