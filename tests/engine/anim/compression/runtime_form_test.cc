// The compressed clip as the server's one runtime form: precision read from
// text, keys given back for export, STEP and unit rotations from the job.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/compression/clip_keys.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/anim/compression/error_bound.h"
#include "../../testing/shared_clips.h"

namespace armature {
namespace {

std::shared_ptr<const Clip> Cmu() { return test_util::SharedCmuClip(); }

TEST(RuntimeForm, PrecisionTextIsExactOrABoundInCentimetres) {
  auto exact = ParseClipPrecision("exact", "precision");
  ASSERT_TRUE(exact.ok());
  EXPECT_TRUE(exact->exact);
  auto bound = ParseClipPrecision("0.05", "precision");
  ASSERT_TRUE(bound.ok());
  EXPECT_FALSE(bound->exact);
  EXPECT_EQ(bound->centimetres, 0.05);
  ClipPrecision fallback;
  fallback.centimetres = 0.2;
  auto empty = ParseClipPrecision("", "precision", fallback);
  ASSERT_TRUE(empty.ok());
  EXPECT_EQ(empty->centimetres, 0.2);
  EXPECT_EQ(ParseClipPrecision("10", "precision")->centimetres, 10.0);
  for (const char* bad : {"0", "-0.01", "nan", "NaN", "inf", "10.5", "abc", "0.01cm", "Exact", " "}) {
    auto parsed = ParseClipPrecision(bad, "--clip-error");
    ASSERT_FALSE(parsed.ok()) << bad;
    EXPECT_EQ(parsed.status().code(), StatusCode::kInvalidArgument) << bad;
    EXPECT_EQ(parsed.status().message().rfind("--clip-error: ", 0), 0u) << parsed.status().message();
  }
  for (double cm : {0.01, 0.1, 1.0 / 3, 7.25, 10.0}) {
    ClipPrecision p;
    p.centimetres = cm;
    EXPECT_EQ(ParseClipPrecision(ClipPrecisionText(p), "precision")->centimetres, cm) << ClipPrecisionText(p);
  }
  EXPECT_EQ(ClipPrecisionText({}), "0.01");
  EXPECT_EQ(ClipPrecisionText(*exact), "exact");
}

// A lossy clip's keys are its samples at its frames (what export writes):
// the stored keys at those times give the job's poses back, within the
// double rounding of making each rotation unit.
TEST(RuntimeForm, KeysOfALossyClipAreItsSamplesAtItsFrames) {
  if (!Cmu()) GTEST_SKIP() << "../shared/data is absent";
  auto lossy = CompressClip(Cmu());
  ASSERT_TRUE(lossy.ok()) << lossy.status().message();
  ASSERT_FALSE((*lossy)->exact());
  auto keys = ClipKeysOf(**lossy);
  ASSERT_TRUE(keys.ok()) << keys.status().message();
  ASSERT_TRUE((*keys)->Validate().ok()) << (*keys)->Validate().message();
  EXPECT_EQ((*keys)->frame_count, (*lossy)->frames.count);
  EXPECT_EQ((*keys)->duration, Cmu()->duration);
  const size_t n = Cmu()->skeleton->size();
  std::vector<Trs> from_keys(n), from_job(n);
  for (size_t f = 0; f < (*lossy)->frames.count; f += 97) {
    const double t = (*lossy)->frames.Time(f);
    ASSERT_TRUE(SampleClip(**keys, t, {}, from_keys).ok());
    ASSERT_TRUE((ClipSamplingJob{lossy->get(), t, WrapMode::kClamp, nullptr, from_job, {}}.Run().ok()));
    for (size_t j = 0; j < n; ++j) {
      EXPECT_LE((from_keys[j].translation - from_job[j].translation).norm(), 1e-12) << f << " " << j;
      EXPECT_LE(from_keys[j].rotation.angularDistance(from_job[j].rotation), 1e-12) << f << " " << j;
    }
  }
  // An exact clip's keys are the stored ones themselves.
  auto exact = CompressClip(Cmu(), ClipPrecision{.exact = true});
  ASSERT_TRUE(exact.ok());
  EXPECT_EQ(*ClipKeysOf(**exact), Cmu());
}

// STEP on a lossy clip holds the frame at or before the time; every rotation
// the job gives is unit in double, as the stored ones are.
TEST(RuntimeForm, StepHoldsTheFrameAndRotationsAreUnit) {
  if (!Cmu()) GTEST_SKIP() << "../shared/data is absent";
  auto lossy = CompressClip(Cmu());
  ASSERT_TRUE(lossy.ok());
  const CompressedClip& z = **lossy;
  const size_t n = z.skeleton->size();
  std::vector<Trs> at_frame(n), between(n), linear(n);
  double worst_norm = 0;
  for (size_t f : {size_t{0}, size_t{15}, size_t{16}, size_t{1000}, z.frames.count - 2}) {
    const double t = z.frames.Time(f), mid = t + 0.6 * z.frames.frame_time;
    ASSERT_TRUE((ClipSamplingJob{&z, t, WrapMode::kClamp, nullptr, at_frame, {}}.Run().ok()));
    ASSERT_TRUE((ClipSamplingJob{&z, mid, WrapMode::kClamp, nullptr, between, Interpolation::kStep}.Run().ok()));
    ASSERT_TRUE((ClipSamplingJob{&z, mid, WrapMode::kClamp, nullptr, linear, {}}.Run().ok()));
    double moved = 0;
    for (size_t j = 0; j < n; ++j) {
      EXPECT_EQ(between[j].translation, at_frame[j].translation) << f << " " << j;
      EXPECT_EQ(between[j].rotation.coeffs(), at_frame[j].rotation.coeffs()) << f << " " << j;
      // Any joint's translation or rotation: a still track may keep equal samples there.
      moved = std::max({moved, (linear[j].translation - at_frame[j].translation).norm(),
                        (linear[j].rotation.coeffs() - at_frame[j].rotation.coeffs()).norm()});
      worst_norm = std::max(worst_norm, std::abs(linear[j].rotation.norm() - 1));
    }
    EXPECT_GT(moved, 0) << "frame " << f << ": LINEAR moves between frames";
  }
  EXPECT_LE(worst_norm, 1e-13);
  EXPECT_EQ((ClipSamplingJob{&z, 0, WrapMode::kClamp, nullptr, at_frame, static_cast<Interpolation>(9)}.Run().code()),
            StatusCode::kInvalidArgument);
}

// A joint subset decodes only its joints' tracks: each equals the whole
// pose's (with a context and without), every other joint is left as it was.
TEST(RuntimeForm, AJointSubsetSamplesItsJointsAsTheWholePose) {
  if (!Cmu()) GTEST_SKIP() << "../shared/data is absent";
  auto lossy = CompressClip(Cmu());
  auto other = CompressClip(Cmu());
  ASSERT_TRUE(lossy.ok() && other.ok());
  const CompressedClip& z = **lossy;
  const size_t n = z.skeleton->size();
  const std::vector<uint32_t> joints = {0, 7, 8, 9, static_cast<uint32_t>(n - 1)};
  const ClipJointSubset subset(z, joints);
  ClipSamplingContext whole_context(z), subset_context(z);
  Trs untouched;
  untouched.translation = Eigen::Vector3d(1e6, 2e6, 3e6);
  std::vector<Trs> whole(n), part(n), no_context(n);
  for (double t = 0; t < 3.0; t += 0.137) {
    std::fill(part.begin(), part.end(), untouched);
    std::fill(no_context.begin(), no_context.end(), untouched);
    ASSERT_TRUE((ClipSamplingJob{&z, t, WrapMode::kClamp, &whole_context, whole, {}}.Run().ok()));
    ASSERT_TRUE((ClipSamplingJob{&z, t, WrapMode::kClamp, &subset_context, part, {}, &subset}.Run().ok()));
    ASSERT_TRUE((ClipSamplingJob{&z, t, WrapMode::kClamp, nullptr, no_context, {}, &subset}.Run().ok()));
    for (size_t j = 0; j < n; ++j) {
      const bool in = std::find(joints.begin(), joints.end(), j) != joints.end();
      for (const std::vector<Trs>* pose : {&part, &no_context}) {
        const Trs& expected = in ? whole[j] : untouched;
        EXPECT_EQ((*pose)[j].translation, expected.translation) << t << " " << j;
        EXPECT_EQ((*pose)[j].rotation.coeffs(), expected.rotation.coeffs()) << t << " " << j;
      }
    }
  }
  const ClipJointSubset elsewhere(**other, joints);
  EXPECT_EQ((ClipSamplingJob{&z, 0, WrapMode::kClamp, nullptr, part, {}, &elsewhere}.Run().code()),
            StatusCode::kInvalidArgument);
}

// The crowd's float path: the same pose as the double job, within float
// rounding (rotations unit in float, no Newton step), playing in order
// through segment ends and wrapping around.
TEST(RuntimeForm, TheFloatJobIsTheDoubleJobInFloat) {
  if (!Cmu()) GTEST_SKIP() << "../shared/data is absent";
  auto lossy = CompressClip(Cmu());
  ASSERT_TRUE(lossy.ok());
  const CompressedClip& z = **lossy;
  ASSERT_FALSE(z.exact());
  const size_t n = z.skeleton->size();
  ClipSamplingContext context(z);
  std::vector<float> lanes(10 * n);
  const FloatPose pose{{lanes.data(), 4 * n}, {lanes.data() + 4 * n, 3 * n}, {lanes.data() + 7 * n, 3 * n}};
  std::vector<Trs> expected(n);
  double worst_angle = 0, worst_unit = 0, worst_vector = 0;
  int samples = 0;
  for (double t = 0; t < 1.3 * z.duration; t += 0.0137, ++samples) {
    ASSERT_TRUE((ClipSamplingFloatJob{&z, t, WrapMode::kLoop, &context, pose}.Run().ok()));
    ASSERT_TRUE((ClipSamplingJob{&z, t, WrapMode::kLoop, nullptr, expected, {}}.Run().ok()));
    for (size_t j = 0; j < n; ++j) {
      const float* r = &lanes[4 * j];
      const Eigen::Quaterniond q(r[3], r[0], r[1], r[2]);
      worst_unit = std::max(worst_unit, std::abs(q.norm() - 1));
      const double dot = std::min(1.0, std::abs(q.normalized().dot(expected[j].rotation)));
      worst_angle = std::max(worst_angle, 2 * std::acos(dot));
      for (int c = 0; c < 3; ++c) {
        const double span = std::max(1.0, expected[j].translation.norm());
        worst_vector =
            std::max(worst_vector, std::abs(pose.translations[3 * j + c] - expected[j].translation[c]) / span);
        worst_vector = std::max(worst_vector, std::abs(pose.scales[3 * j + c] - expected[j].scale[c]));
      }
    }
  }
  EXPECT_GT(samples, 300);
  EXPECT_LE(worst_unit, 1e-6);
  EXPECT_LE(worst_angle, 2e-6);  // float rounding, far below the crowd encoding's 1.5e-4
  EXPECT_LE(worst_vector, 1e-6);
  EXPECT_EQ((ClipSamplingFloatJob{&z, 0, WrapMode::kLoop, nullptr, pose}.Run().code()), StatusCode::kInvalidArgument);
  const FloatPose short_pose{pose.rotations.first(4 * n - 1), pose.translations, pose.scales};
  EXPECT_EQ((ClipSamplingFloatJob{&z, 0, WrapMode::kLoop, &context, short_pose}.Run().code()),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace armature
