// The crowd ticker's motion path (issue 31) on CMU 01_01 blended with
// itself 0.3 / 0.7: decoded poses equal BlendMotionJob's at each character's
// motion time (offset + speed·t, not wrapped) within the encoding's bound,
// beside clip characters in the same tick; one plan is one layout.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/crowd/crowd_motion.h"
#include "armature/engine/anim/crowd/crowd_ticker.h"
#include "cmu_clip.h"

namespace armature {
namespace {

std::shared_ptr<const MotionPlan> TwoLayers() {
  Motion motion;
  motion.layers.push_back({.clip = Cmu(), .clip_name = "cmu", .weight = 0.3});
  motion.layers.push_back({.clip = Cmu(), .clip_name = "cmu", .weight = 0.7, .time_offset = 0.6});
  StatusOr<MotionPlan> plan = BindMotion(motion);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  return std::make_shared<const MotionPlan>(std::move(*plan));
}

double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return 2 * std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized()))));
}

TEST(CrowdTickerMotionTest, DecodedPosesAreTheBlendAtEachCharactersMotionTime) {
  if (!Cmu()) GTEST_SKIP() << "../shared/data is absent";
  const std::shared_ptr<const MotionPlan> plan = TwoLayers();
  CrowdTicker ticker({.budget_us = 1e6, .share_quantum = 1.0 / 120});
  const uint32_t motion = *ticker.AddMotion(plan);
  EXPECT_EQ(*ticker.AddMotion(plan), motion);  // the same plan: one layout
  const uint32_t clip = *ticker.AddClip(Cmu());
  EXPECT_NE(clip, motion);
  for (uint32_t id = 0; id < 20; ++id)
    ASSERT_TRUE(
        ticker.Add({.id = id, .clip = id % 2 ? clip : motion, .time_offset = 0.3 * id, .speed = 0.5 + 0.1 * id}).ok());
  CrowdMotion blend{plan, {}};
  blend.workspace.Resize(*plan);
  std::vector<Trs> decoded(plan->skeleton->size()), expected(plan->skeleton->size());
  double worst = 0, moved = 0;
  size_t compared = 0;
  CrowdTick tick;
  for (uint64_t k = 0; k < 12; ++k) {
    const double time = k / 30.0;
    ASSERT_TRUE(ticker.Tick(k, time, &tick).ok());
    size_t offset = 0;
    for (size_t i = 0; i < tick.ids.size(); ++i) {
      const PoseLayout& layout = ticker.layout(tick.clips[i]);
      std::span<const uint8_t> bytes(tick.poses.data() + offset, layout.EncodedSize());
      offset += layout.EncodedSize();
      if (tick.clips[i] != motion) continue;
      const uint32_t id = tick.ids[i];
      EXPECT_NEAR(tick.clip_times[i], 0.3 * id + (0.5 + 0.1 * id) * time, 0.5 / 120 + 1e-12);  // rounded to 1/120 s
      ASSERT_TRUE(DecodePose(layout, bytes, decoded).ok());
      ASSERT_TRUE(SampleCrowdMotion(blend, tick.clip_times[i], expected).ok());
      for (size_t j = 0; j < decoded.size(); ++j) {
        worst = std::max(worst, AngleBetween(decoded[j].rotation, expected[j].rotation));
        moved = std::max(moved, AngleBetween(decoded[j].rotation, layout.base[j].rotation));
        ASSERT_LE((decoded[j].translation - expected[j].translation).norm(), 1e-4) << "joint " << j;
      }
      ++compared;
    }
    EXPECT_EQ(offset, tick.poses.size());
  }
  EXPECT_GE(compared, 80u);  // 10 motion characters over 12 ticks, the first ones staggered
  EXPECT_LE(worst, MaxEncodedRotationError());
  EXPECT_GT(moved, 0.1);  // the poses move: the comparison has teeth
}

TEST(CrowdTickerMotionTest, CharactersAtOneQuantizedMotionTimeShareOneBlend) {
  if (!Cmu()) GTEST_SKIP() << "../shared/data is absent";
  CrowdTicker ticker({.budget_us = 1e6, .share_quantum = 0.1});
  const uint32_t motion = *ticker.AddMotion(TwoLayers());
  for (uint32_t id = 0; id < 8; ++id)  // two groups, each within one 0.1 s quantum
    ASSERT_TRUE(ticker.Add({.id = id, .clip = motion, .time_offset = id < 4 ? 1.0 + 0.01 * id : 5.0}).ok());
  CrowdTick tick;
  size_t updated = 0, samples = 0;
  for (uint64_t k = 0; k < 10; ++k) {
    ASSERT_TRUE(ticker.Tick(k, k / 30.0, &tick).ok());
    updated += tick.ids.size();
    samples += tick.samples;
    const size_t bytes = ticker.layout(motion).EncodedSize();
    for (size_t i = 0; i < tick.ids.size(); ++i)
      for (size_t o = 0; o < i; ++o)  // equal rounded times, equal bytes
        if (tick.clip_times[i] == tick.clip_times[o])
          EXPECT_EQ(std::memcmp(&tick.poses[i * bytes], &tick.poses[o * bytes], bytes), 0);
  }
  EXPECT_GE(updated, 60u);
  EXPECT_LE(samples * 3, updated);  // about 2 blends a tick for 8 characters
}

TEST(CrowdTickerMotionTest, TheLayoutSendsTheTranslationsTheClipsAnimate) {
  if (!Cmu()) GTEST_SKIP() << "../shared/data is absent";
  const StatusOr<PoseLayout> motion = LayoutOfMotion(*TwoLayers());
  const StatusOr<PoseLayout> clip = LayoutOfClip(*Cmu());
  ASSERT_TRUE(motion.ok() && clip.ok());
  EXPECT_EQ(motion->joints, clip->joints);
  for (uint16_t j : clip->translated)  // every joint whose translation varies in the clip varies in the blend
    EXPECT_NE(std::find(motion->translated.begin(), motion->translated.end(), j), motion->translated.end());
  EXPECT_LE(motion->EncodedSize(), 8u * motion->joints);
}

TEST(CrowdTickerMotionTest, NonFiniteNumbersAndNoPlanAreRefused) {
  if (!Cmu()) GTEST_SKIP() << "../shared/data is absent";
  CrowdTicker ticker({});
  EXPECT_FALSE(ticker.AddMotion(nullptr).ok());
  const uint32_t motion = *ticker.AddMotion(TwoLayers());
  const Status st = ticker.Add({.id = 4, .clip = motion, .speed = std::nan("")});
  EXPECT_FALSE(st.ok());
  EXPECT_EQ(st.message().rfind("character 4: ", 0), 0u) << st.message();
}

}  // namespace
}  // namespace armature
