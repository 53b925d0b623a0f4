// The crowd ticker (issue 31) on CMU 01_01: decoded poses equal the sampling
// job's at each character's clip time within the encoding's bound, sharing
// samples once per (clip, quantized time), a short budget defers the least
// significant, the schedule is deterministic, and bad characters are named.
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/crowd/crowd_ticker.h"
#include "cmu_clip.h"

namespace armature {
namespace {

#define SKIP_WITHOUT_CMU() \
  if (!Cmu()) GTEST_SKIP() << "../shared/data is absent"

double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return 2 * std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized()))));
}

// Every pose of `tick` against the sampling job at its clip time.
void ExpectPosesMatch(const CrowdTicker& ticker, uint32_t clip, const CrowdTick& tick) {
  const PoseLayout& layout = ticker.layout(clip);
  std::vector<Trs> decoded(layout.joints), expected(layout.joints);
  ASSERT_EQ(tick.poses.size(), tick.ids.size() * layout.EncodedSize());
  for (size_t i = 0; i < tick.ids.size(); ++i) {
    std::span<const uint8_t> bytes(tick.poses.data() + i * layout.EncodedSize(), layout.EncodedSize());
    ASSERT_TRUE(DecodePose(layout, bytes, decoded).ok());
    ASSERT_TRUE(
        (ClipSamplingJob{&ticker.clip(clip), tick.clip_times[i], WrapMode::kLoop, nullptr, expected, std::nullopt}
             .Run()
             .ok()));
    for (size_t j = 0; j < layout.joints; ++j) {
      ASSERT_LE(AngleBetween(decoded[j].rotation, expected[j].rotation), MaxEncodedRotationError());
      ASSERT_LE((decoded[j].translation - expected[j].translation).norm(), 1e-4);
    }
  }
}

TEST(CrowdTickerTest, DecodedPosesAreTheClipAtEachCharactersTime) {
  SKIP_WITHOUT_CMU();
  CrowdTicker ticker({.budget_us = 1e6});
  const uint32_t clip = *ticker.AddClip(Cmu());
  for (uint32_t id = 0; id < 50; ++id)
    ASSERT_TRUE(ticker.Add({.id = id, .clip = clip, .time_offset = 0.37 * id, .speed = 0.5 + 0.02 * id}).ok());
  CrowdTick tick;
  ASSERT_TRUE(ticker.Tick(3, 0.1, &tick).ok());
  ASSERT_EQ(tick.ids.size(), 50u);
  EXPECT_EQ(tick.deferred, 0u);
  EXPECT_EQ(tick.samples, 50u);
  for (size_t i = 0; i < tick.ids.size(); ++i) {
    const uint32_t id = tick.ids[i];
    const double expected = WrapTime(0.37 * id + (0.5 + 0.02 * id) * 0.1, Cmu()->duration, WrapMode::kLoop);
    EXPECT_DOUBLE_EQ(tick.clip_times[i], expected) << id;
  }
  ExpectPosesMatch(ticker, clip, tick);
  EXPECT_EQ(tick.poses.size(), 50u * (31 * 6 + 12));
}

// Characters due one after the other in one segment reuse its header (the
// ticker's context per clip): their bytes are those of a pose sampled alone
// (the float job with a fresh context, no header carried over).
TEST(CrowdTickerTest, CharactersCloseInTimeEncodeTheirOwnSamples) {
  SKIP_WITHOUT_CMU();
  CrowdTicker ticker({.budget_us = 1e6});
  const uint32_t clip = *ticker.AddClip(Cmu());
  for (uint32_t id = 0; id < 40; ++id)
    ASSERT_TRUE(ticker.Add({.id = id, .clip = clip, .time_offset = 0.0137 * id}).ok());
  const PoseLayout& layout = ticker.layout(clip);
  const size_t n = layout.joints;
  std::vector<float> lanes(10 * n);
  const FloatPose alone{{lanes.data(), 4 * n}, {lanes.data() + 4 * n, 3 * n}, {lanes.data() + 7 * n, 3 * n}};
  std::vector<uint8_t> bytes(layout.EncodedSize());
  CrowdTick tick;
  for (uint64_t k = 0; k < 6; ++k) {
    ASSERT_TRUE(ticker.Tick(k, static_cast<double>(k) / 30, &tick).ok());
    ASSERT_EQ(tick.ids.size(), 40u);
    for (size_t i = 0; i < tick.ids.size(); ++i) {
      ClipSamplingContext fresh(*Cmu());
      ASSERT_TRUE((ClipSamplingFloatJob{Cmu().get(), tick.clip_times[i], WrapMode::kLoop, &fresh, alone}.Run().ok()));
      EncodePose(layout, alone, bytes.data());
      EXPECT_TRUE(std::equal(bytes.begin(), bytes.end(), tick.poses.begin() + i * bytes.size())) << k << " " << i;
    }
  }
}

TEST(CrowdTickerTest, CharactersAtOneQuantizedTimeShareOneSample) {
  SKIP_WITHOUT_CMU();
  CrowdTicker ticker({.budget_us = 1e6, .share_quantum = 1.0 / 60});
  const uint32_t clip = *ticker.AddClip(Cmu());
  // 1,000 characters on 10 offsets, each jittered by under half a quantum.
  for (uint32_t id = 0; id < 1000; ++id)
    ASSERT_TRUE(ticker.Add({.id = id, .clip = clip, .time_offset = 0.5 * (id % 10) + 0.001 * (id % 7)}).ok());
  CrowdTick tick;
  ASSERT_TRUE(ticker.Tick(0, 1.0, &tick).ok());
  EXPECT_EQ(tick.ids.size(), 1000u);
  EXPECT_EQ(tick.samples, 10u);
  std::set<double> times(tick.clip_times.begin(), tick.clip_times.end());
  EXPECT_EQ(times.size(), 10u);
  for (double t : times) EXPECT_NEAR(std::remainder(t, 1.0 / 60), 0, 1e-9);
  ExpectPosesMatch(ticker, clip, tick);
}

TEST(CrowdTickerTest, AShortBudgetDefersTheLeastSignificant) {
  SKIP_WITHOUT_CMU();
  // A fixed cost of 1 µs an update and 250 µs: 250 updates a tick for 1,000 characters.
  CrowdTicker ticker({.budget_us = 250, .max_interval = 8, .fixed_cost_us = 1});
  const uint32_t clip = *ticker.AddClip(Cmu());
  for (uint32_t id = 0; id < 1000; ++id)
    ASSERT_TRUE(ticker.Add({.id = id, .clip = clip, .time_offset = 0.01 * id, .significance = -double(id)}).ok());
  CrowdTick tick;
  std::vector<int> updates(1000, 0);
  size_t most = 0;
  for (uint64_t k = 0; k < 80; ++k) {
    ASSERT_TRUE(ticker.Tick(k, k / 30.0, &tick).ok());
    most = std::max(most, tick.ids.size());
    EXPECT_EQ(tick.deferred, 1000 - tick.ids.size());
    if (k >= 16)
      for (uint32_t id : tick.ids) ++updates[id];
  }
  EXPECT_LE(most, 250u);
  EXPECT_GT(tick.reduced, 800u);
  EXPECT_EQ(updates[0], 64);        // the most significant: every tick
  EXPECT_GE(updates[999], 64 / 9);  // the least: every 8 ticks, 9 at worst
  EXPECT_LE(updates[999], 64 / 8 + 1);
  ExpectPosesMatch(ticker, clip, tick);
}

TEST(CrowdTickerTest, TheScheduleIsDeterministicForAFixedCost) {
  SKIP_WITHOUT_CMU();
  CrowdTicker a({.budget_us = 100, .fixed_cost_us = 1}), b({.budget_us = 100, .fixed_cost_us = 1});
  for (CrowdTicker* t : {&a, &b}) {
    const uint32_t clip = *t->AddClip(Cmu());
    for (uint32_t id = 0; id < 300; ++id)
      ASSERT_TRUE(t->Add({.id = id, .clip = clip, .time_offset = 0.1 * id, .significance = double(id % 17)}).ok());
  }
  CrowdTick ta, tb;
  for (uint64_t k = 0; k < 20; ++k) {
    ASSERT_TRUE(a.Tick(k, k / 30.0, &ta).ok());
    ASSERT_TRUE(b.Tick(k, k / 30.0, &tb).ok());
    EXPECT_EQ(ta.ids, tb.ids);
    EXPECT_EQ(ta.poses, tb.poses);
  }
}

TEST(CrowdTickerTest, BadCharactersAreNamed) {
  SKIP_WITHOUT_CMU();
  CrowdTicker ticker({});
  const uint32_t clip = *ticker.AddClip(Cmu());
  ASSERT_TRUE(ticker.Add({.id = 7, .clip = clip}).ok());
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const Status& st :
       {ticker.Add({.id = 7, .clip = clip}), ticker.Update({.id = 8, .clip = clip}), ticker.Remove(8),
        ticker.Add({.id = 9, .clip = 5}), ticker.Add({.id = 9, .clip = clip, .speed = nan}),
        ticker.Add({.id = 9, .clip = clip, .time_offset = inf}),
        ticker.Update({.id = 7, .clip = clip, .significance = nan})}) {
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(st.message().find("character "), std::string::npos) << st.message();
  }
  EXPECT_EQ(ticker.size(), 1u);
  EXPECT_TRUE(ticker.Remove(7).ok());
  EXPECT_EQ(ticker.size(), 0u);
  CrowdTick tick;
  EXPECT_TRUE(ticker.Tick(0, 0, &tick).ok());
  EXPECT_TRUE(tick.ids.empty());
}

}  // namespace
}  // namespace armature
