// Clips compiled when an asset is parsed, and sampled through that form.
#include "server/assets/compiled_clips.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/compiled_clip.h"
#include "../testing/demo_catalog.h"

namespace armature::server {
namespace {

using test_util::DemoCatalog;

// Largest difference between two poses: radians between rotations; for
// translations and scales, distance relative to the length (at least 1).
double PoseDifference(const std::vector<Trs>& a, const std::vector<Trs>& b) {
  double worst = 0;
  for (size_t j = 0; j < a.size(); ++j) {
    worst = std::max(worst, a[j].rotation.angularDistance(b[j].rotation));
    worst = std::max(worst, (a[j].translation - b[j].translation).norm() / std::max(1.0, a[j].translation.norm()));
    worst = std::max(worst, (a[j].scale - b[j].scale).norm() / std::max(1.0, a[j].scale.norm()));
  }
  return worst;
}

TEST(CompiledClips, EveryParsedClipGetsItsRuntimeForm) {
  auto catalog = DemoCatalog();  // parsed and compiled as the store does
  ASSERT_EQ(catalog->clips.size(), 2u);
  for (const auto& [name, ref] : catalog->clips) {
    ASSERT_NE(ref.part->compiled, nullptr) << name;
    EXPECT_EQ(ref.part->compiled->source, ref.part->clip) << name;
    EXPECT_EQ(RuntimeForm(*ref.part), ref.part->compiled.get()) << name;
  }
}

// SampleNamedClip returns SampleClip's poses (float keys: within 1e-6 of the
// file form, radians and skeleton units) for every interpolation and wrap.
TEST(CompiledClips, SamplingThroughTheRuntimeFormGivesTheFileFormsPoses) {
  auto catalog = DemoCatalog();
  for (const auto& [name, ref] : catalog->clips) {
    const Clip& clip = *ref.part->clip;
    std::vector<Trs> file(clip.skeleton->size()), runtime(file.size());
    for (Interpolation interpolation : {Interpolation::kStep, Interpolation::kLinear, Interpolation::kCubic}) {
      for (WrapMode wrap : {WrapMode::kClamp, WrapMode::kLoop}) {
        SampleOptions options;
        options.interpolation = interpolation;
        options.wrap = wrap;
        for (double t : {0.0, 0.013, 0.31, clip.duration / 2, clip.duration, 1.7 * clip.duration + 0.02}) {
          ASSERT_TRUE(SampleClip(clip, t, options, file).ok());
          ASSERT_TRUE(SampleNamedClip(*ref.part, t, options, runtime).ok());
          EXPECT_LT(PoseDifference(file, runtime), 1e-6) << name << " t=" << t;
        }
      }
    }
    // The same checks as SampleClip: a short output span is refused.
    std::vector<Trs> short_pose(file.size() - 1);
    EXPECT_EQ(SampleNamedClip(*ref.part, 0, {}, short_pose).code(), SampleClip(clip, 0, {}, short_pose).code());
  }
}

// A NamedClip whose compiled form is of another clip (copied, then given a
// new clip) samples its own clip's file form, never the stale runtime form.
TEST(CompiledClips, ARuntimeFormOfAnotherClipIsNotUsed) {
  auto catalog = DemoCatalog();
  const NamedClip& walk = *catalog->FindClip("demo_walk")->part;
  const NamedClip& other = *catalog->FindClip("demo_character.walk")->part;
  NamedClip mixed = walk;
  mixed.compiled = other.compiled;
  EXPECT_EQ(RuntimeForm(mixed), nullptr);
  std::vector<Trs> expected(walk.clip->skeleton->size()), got(expected.size());
  ASSERT_TRUE(SampleClip(*walk.clip, 0.4, {}, expected).ok());
  ASSERT_TRUE(SampleNamedClip(mixed, 0.4, {}, got).ok());
  EXPECT_EQ(PoseDifference(expected, got), 0);
  // No runtime form at all: the file form, exactly.
  mixed.compiled = nullptr;
  ASSERT_TRUE(SampleNamedClip(mixed, 0.4, {}, got).ok());
  EXPECT_EQ(PoseDifference(expected, got), 0);
}

// The benchmark's switch: the file form for every clip while set.
TEST(CompiledClips, TheBenchmarkSwitchSamplesTheFileForm) {
  auto catalog = DemoCatalog();
  const NamedClip& walk = *catalog->FindClip("demo_walk")->part;
  SampleFileFormOnly(true);
  EXPECT_EQ(RuntimeForm(walk), nullptr);
  SampleFileFormOnly(false);
  EXPECT_EQ(RuntimeForm(walk), walk.compiled.get());
}

}  // namespace
}  // namespace armature::server
