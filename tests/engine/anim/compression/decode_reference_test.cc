// The sampling job decodes every lossy clip of ../shared/data bit for bit as
// a plain decoder of the format does (reference_decoder.h): at and between
// frames, in order through a context, at random with and without one, and
// through a joint subset. Its fast paths (one read per sample, rotations
// four at a time, cheap header walks) change speed, never values; so does
// its AVX2 clone, run here beside the baseline where the CPU has AVX2.
#include <algorithm>
#include <cstring>
#include <iostream>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "../../testing/shared_clips.h"
#include "anim/compression/sampling_isa.h"
#include "reference_decoder.h"

namespace armature {
namespace {

struct LossyClip {
  std::string name;
  std::shared_ptr<const CompressedClip> clip;
};

const std::vector<LossyClip>& LossyClips() {
  static const std::vector<LossyClip> clips = [] {
    std::vector<LossyClip> out;
    for (const test_util::SharedClip& c : test_util::LoadSharedClips()) {
      auto z = CompressClip(c.clip);
      if (z.ok() && !(*z)->exact() && !(*z)->animated.empty()) out.push_back({c.name, *z});
    }
    return out;
  }();
  return clips;
}

bool SameBits(const Trs& a, const Trs& b) {
  return std::memcmp(a.translation.data(), b.translation.data(), 3 * sizeof(double)) == 0 &&
         std::memcmp(a.rotation.coeffs().data(), b.rotation.coeffs().data(), 4 * sizeof(double)) == 0 &&
         std::memcmp(a.scale.data(), b.scale.data(), 3 * sizeof(double)) == 0;
}

// Times at every frame, a third and two thirds of the way to the next, and
// past both ends.
std::vector<double> Times(const CompressedClip& z) {
  std::vector<double> times = {-1.0, z.duration + 1.0};
  for (size_t f = 0; f < z.frames.count; ++f)
    for (double part : {0.0, 1.0 / 3, 2.0 / 3}) times.push_back((static_cast<double>(f) + part) * z.frames.frame_time);
  return times;
}

// Counts the joints of `pose` that differ from the reference in any bit.
size_t Mismatches(const std::vector<Trs>& pose, const std::vector<Trs>& expected, const std::vector<uint32_t>* only) {
  size_t bad = 0;
  for (size_t j = 0; j < pose.size(); ++j)
    if ((!only || std::binary_search(only->begin(), only->end(), j)) && !SameBits(pose[j], expected[j])) ++bad;
  return bad;
}

void DecodeEveryClipAsTheReference();

// The builds of the job's core this CPU runs: the baseline, and the AVX2
// clone when it can. Each test leaves the job on the CPU's own choice.
std::vector<bool> Builds() {
  if (compression_internal::CpuRunsSamplingAvx2()) return {false, true};
  std::cout << "[   NOTE   ] this CPU has no AVX2 and BMI2: the AVX2 clone is not run\n";
  return {false};
}

struct CpuChoice {
  ~CpuChoice() { compression_internal::UseSamplingAvx2(true); }
};

TEST(DecodeReference, InOrderAtRandomAndThroughASubsetTheJobDecodesAsThePlainDecoder) {
  if (LossyClips().empty()) GTEST_SKIP() << "../shared/data is absent: no real clips to compress";
  const CpuChoice restore;
  for (const bool avx2 : Builds()) {
    compression_internal::UseSamplingAvx2(avx2);
    ASSERT_EQ(compression_internal::SamplingUsesAvx2(), avx2);
    SCOPED_TRACE(avx2 ? "AVX2 clone" : "baseline");
    DecodeEveryClipAsTheReference();
  }
}

// The float lanes (ClipSamplingFloatJob, the crowd's and the blend's) have
// no plain decoder of their own: the two builds agree on them bit for bit.
TEST(DecodeReference, TheAvx2CloneGivesTheBaselinesFloatLanes) {
  if (LossyClips().empty()) GTEST_SKIP() << "../shared/data is absent: no real clips to compress";
  if (!compression_internal::CpuRunsSamplingAvx2()) GTEST_SKIP() << "this CPU has no AVX2 and BMI2";
  const CpuChoice restore;
  size_t lanes_compared = 0;
  for (const LossyClip& c : LossyClips()) {
    const CompressedClip& z = *c.clip;
    const size_t n = z.skeleton->size();
    std::vector<float> lanes[2] = {std::vector<float>(10 * n), std::vector<float>(10 * n)};
    ClipSamplingContext contexts[2] = {ClipSamplingContext(z), ClipSamplingContext(z)};
    for (const double t : Times(z)) {
      for (int b = 0; b < 2; ++b) {
        compression_internal::UseSamplingAvx2(b == 1);
        const std::span<float> l(lanes[b]);
        const FloatPose pose{l.subspan(0, 4 * n), l.subspan(4 * n, 3 * n), l.subspan(7 * n, 3 * n)};
        ASSERT_TRUE((ClipSamplingFloatJob{&z, t, WrapMode::kClamp, &contexts[b], pose}.Run().ok()));
      }
      ASSERT_EQ(std::memcmp(lanes[0].data(), lanes[1].data(), lanes[0].size() * sizeof(float)), 0)
          << c.name << " at t = " << t << ": the clone's float lanes differ from the baseline's";
      lanes_compared += lanes[0].size();
    }
  }
  EXPECT_GT(lanes_compared, 100000u);
}

void DecodeEveryClipAsTheReference() {
  size_t poses = 0, rotated_segments = 0;
  for (const LossyClip& c : LossyClips()) {
    const CompressedClip& z = *c.clip;
    const test_util::ReferenceDecoder reference(z);
    const size_t n = z.skeleton->size();
    std::vector<uint32_t> every_other;
    for (uint32_t j = 0; j < n; j += 2) every_other.push_back(j);
    const ClipJointSubset subset(z, every_other);
    std::vector<double> ordered = Times(z), shuffled = ordered;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(30));
    ClipSamplingContext in_order(z), at_random(z), subset_context(z);
    std::vector<Trs> pose(n), expected;
    size_t bad = 0;
    for (const double t : ordered) {
      expected = reference.Pose(t);
      ASSERT_TRUE((ClipSamplingJob{&z, t, WrapMode::kClamp, &in_order, pose, {}}.Run().ok()));
      bad += Mismatches(pose, expected, nullptr);
      ++poses;
    }
    for (const double t : shuffled) {
      expected = reference.Pose(t);
      ASSERT_TRUE((ClipSamplingJob{&z, t, WrapMode::kClamp, &at_random, pose, {}}.Run().ok()));
      bad += Mismatches(pose, expected, nullptr);
      ASSERT_TRUE((ClipSamplingJob{&z, t, WrapMode::kClamp, nullptr, pose, {}}.Run().ok()));
      bad += Mismatches(pose, expected, nullptr);
      ASSERT_TRUE((ClipSamplingJob{&z, t, WrapMode::kClamp, &subset_context, pose, {}, &subset}.Run().ok()));
      bad += Mismatches(pose, expected, &every_other);
      ASSERT_TRUE((ClipSamplingJob{&z, t, WrapMode::kClamp, nullptr, pose, {}, &subset}.Run().ok()));
      bad += Mismatches(pose, expected, &every_other);
      poses += 4;
    }
    EXPECT_EQ(bad, 0u) << c.name << ": joints decoded differently from the plain decoder";
    for (const AnimatedTrack& track : z.animated) rotated_segments += track.dropped != 3;
  }
  EXPECT_GT(poses, 40000u);
  EXPECT_GT(rotated_segments, 0u) << "no track drops another component than w: that path went untested";
}

}  // namespace
}  // namespace armature
