// The sampling job decodes every lossy clip of ../shared/data bit for bit as
// a plain decoder of the format does (reference_decoder.h): at and between
// frames, in order through a context, at random with and without one, and
// through a joint subset. Its fast paths (one read per sample, rotations
// four at a time, cheap header walks) change speed, never values.
#include <algorithm>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "../../testing/shared_clips.h"
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

TEST(DecodeReference, InOrderAtRandomAndThroughASubsetTheJobDecodesAsThePlainDecoder) {
  if (LossyClips().empty()) GTEST_SKIP() << "../shared/data is absent: no real clips to compress";
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
