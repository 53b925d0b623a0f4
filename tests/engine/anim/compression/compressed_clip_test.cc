// The compressed runtime clip (issue 30) on the real files of ../shared/data:
// the bound holds on every clip, `exact` keeps the stored keys, bad bounds
// are refused, tracks are ordered for seeks, and the sampling job agrees
// with itself played in order or at random and through a joint map.
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/anim/compression/error_bound.h"
#include "armature/engine/anim/compression/shell_error.h"
#include "armature/engine/anim/joint_map.h"
#include "armature/engine/io/bvh/bvh.h"
#include "anim/compression/packed_track.h"
#include "../../testing/shared_clips.h"

namespace armature {
namespace {

const std::vector<test_util::SharedClip>& Clips() {
  static const std::vector<test_util::SharedClip> clips = test_util::LoadSharedClips();
  return clips;
}

std::shared_ptr<const Clip> Cmu() {
  for (const test_util::SharedClip& c : Clips())
    if (c.name == "bvh/cmu_01_01.bvh") return c.clip;
  return nullptr;
}

#define SKIP_WITHOUT_SHARED_DATA() \
  if (Clips().empty()) GTEST_SKIP() << "../shared/data is absent: no real clips to compress"

bool SameBits(const Trs& a, const Trs& b) {
  return std::memcmp(a.translation.data(), b.translation.data(), 3 * sizeof(double)) == 0 &&
         std::memcmp(a.rotation.coeffs().data(), b.rotation.coeffs().data(), 4 * sizeof(double)) == 0 &&
         std::memcmp(a.scale.data(), b.scale.data(), 3 * sizeof(double)) == 0;
}

TEST(CompressedClipTest, BadBoundsAreRefusedNamingPrecision) {
  SKIP_WITHOUT_SHARED_DATA();
  for (double cm :
       {0.0, -0.01, std::numeric_limits<double>::quiet_NaN(), 10.0001, std::numeric_limits<double>::infinity()}) {
    ClipPrecision precision;
    precision.centimetres = cm;
    StatusOr<std::shared_ptr<const CompressedClip>> c = CompressClip(Cmu(), precision);
    ASSERT_FALSE(c.ok()) << cm;
    EXPECT_EQ(c.status().code(), StatusCode::kInvalidArgument) << cm;
    EXPECT_NE(c.status().message().find("precision"), std::string::npos) << c.status().message();
  }
  ClipPrecision ten;
  ten.centimetres = 10;
  EXPECT_TRUE(CompressClip(Cmu(), ten).ok());
}

TEST(CompressedClipTest, UnitsAreMetresForGltfAndBySpanForBvh) {
  SKIP_WITHOUT_SHARED_DATA();
  EXPECT_EQ(UnitsPerCentimetre(*Cmu()->skeleton), 1.0);  // CMU's body spans about 35 units
  Skeleton metres;                                       // a BVH skeleton 1.7 units tall
  metres.names = {"hips", "head"};
  metres.parents = {-1, 0};
  metres.rest.resize(2);
  metres.rest[1].translation = Eigen::Vector3d(0, 1.7, 0);
  metres.channels = {{Channel::kXrotation}, {Channel::kXrotation}};
  metres.end_sites.resize(2);
  EXPECT_EQ(UnitsPerCentimetre(metres), 0.01);
  Skeleton gltf = metres;  // no channels: glTF, metres whatever its span
  gltf.channels.assign(2, {});
  gltf.rest[1].translation = Eigen::Vector3d(0, 170, 0);
  EXPECT_EQ(UnitsPerCentimetre(gltf), 0.01);
  StatusOr<ErrorBound> bound = ResolveErrorBound(metres, {});
  ASSERT_TRUE(bound.ok());
  EXPECT_DOUBLE_EQ(bound->precision, 0.0001);
  EXPECT_DOUBLE_EQ(bound->shell_distance, 0.03);
}

// The stated bound holds on every clip: its worst error, measured again here
// over every frame through the sampling job, is within it.
TEST(CompressedClipTest, TheBoundHoldsOnEveryClip) {
  SKIP_WITHOUT_SHARED_DATA();
  for (const test_util::SharedClip& c : Clips()) {
    StatusOr<std::shared_ptr<const CompressedClip>> compressed = CompressClip(c.clip);
    ASSERT_TRUE(compressed.ok()) << c.name << ": " << compressed.status().message();
    const CompressedClip& z = **compressed;
    EXPECT_EQ(z.exact(), !z.warning.empty()) << c.name << " is exact only with a warning";
    const PoseSampler job = [&](double t, std::span<Trs> out) {
      return ClipSamplingJob{&z, t, WrapMode::kClamp, nullptr, out, {}}.Run();
    };
    StatusOr<ClipError> error = MeasureClipError(*c.clip, z.frames, z.bound.shell_distance, job);
    ASSERT_TRUE(error.ok()) << c.name;
    EXPECT_LE(error->worst, z.bound.precision) << c.name;
    EXPECT_LE(z.error.worst, z.bound.precision) << c.name;
    std::printf("%-52s %3zu joints %5zu frames %6.3f bytes/joint-sample, p99 %.5f worst %.5f (bound %.5f)%s\n",
                c.name.c_str(), c.clip->skeleton->size(), z.frames.count, z.BytesPerJointSample(), error->p99,
                error->worst, z.bound.precision, z.warning.c_str());
  }
}

// A joint whose child is a million units away turns every rotation error
// into a displacement no 23-bit track can keep under 0.01: stored exact,
// with a warning naming why, never above the bound.
TEST(CompressedClipTest, AClipThatCannotMeetTheBoundIsKeptExactWithAWarning) {
  auto skeleton = std::make_shared<Skeleton>();
  skeleton->names = {"root", "far"};
  skeleton->parents = {-1, 0};
  skeleton->rest.resize(2);
  skeleton->rest[1].translation = Eigen::Vector3d(1e6, 0, 0);
  skeleton->channels = {{Channel::kZrotation}, {}};
  skeleton->end_sites.resize(2);
  auto clip = std::make_shared<Clip>();
  clip->skeleton = skeleton;
  clip->joints.resize(2);
  for (int k = 0; k < 40; ++k) {
    clip->joints[0].rotation.times.push_back(k / 30.0);
    clip->joints[0].rotation.values.push_back(
        Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * k * k, Eigen::Vector3d(0.3, 1, 0.2).normalized())));
  }
  clip->duration = 39 / 30.0;
  clip->frame_count = 40;
  StatusOr<std::shared_ptr<const CompressedClip>> z = CompressClip(clip);
  ASSERT_TRUE(z.ok()) << z.status().message();
  EXPECT_TRUE((*z)->exact());
  EXPECT_TRUE((*z)->precision.exact);
  EXPECT_NE((*z)->warning.find("kept exact"), std::string::npos) << (*z)->warning;
  EXPECT_EQ((*z)->error.worst, 0.0);
}

// Two keys of one rotating joint, `seconds` apart.
std::shared_ptr<Clip> TwoKeys(double seconds) {
  auto skeleton = std::make_shared<Skeleton>();
  skeleton->names = {"root"};
  skeleton->parents = {-1};
  skeleton->rest.resize(1);
  skeleton->channels = {{Channel::kZrotation}};
  skeleton->end_sites.resize(1);
  auto clip = std::make_shared<Clip>();
  clip->skeleton = skeleton;
  clip->joints.resize(1);
  clip->joints[0].rotation.times = {0, seconds};
  clip->joints[0].rotation.values = {Eigen::Quaterniond::Identity(),
                                     Eigen::Quaterniond(Eigen::AngleAxisd(1, Eigen::Vector3d::UnitZ()))};
  clip->duration = seconds;
  clip->frame_count = 2;
  return clip;
}

// Keys far apart would be checked at 30 frames a second on a reference of
// about 200 bytes a joint-sample: past kMaxResampledJointSamples the clip
// is kept exact instead. (A 600-byte BVH with a frame time of a year asked
// CompressClip for 500 GB; fuzz/engine_compress_fuzz found it.)
TEST(CompressedClipTest, KeysTooFarApartToResampleAreKeptExactWithAWarning) {
  const double cap = kMaxResampledJointSamples;
  const std::optional<FrameGrid> at_cap = CompressionFrames(*TwoKeys((cap - 1) / 30));
  ASSERT_TRUE(at_cap.has_value());
  EXPECT_EQ(at_cap->count, static_cast<size_t>(cap));
  EXPECT_FALSE(CompressionFrames(*TwoKeys(cap / 30)).has_value());

  const std::shared_ptr<Clip> year = TwoKeys(3.15e7);
  StatusOr<std::shared_ptr<const CompressedClip>> z = CompressClip(year);
  ASSERT_TRUE(z.ok()) << z.status().message();
  EXPECT_TRUE((*z)->exact());
  EXPECT_NE((*z)->warning.find("at 30 a second"), std::string::npos) << (*z)->warning;
  EXPECT_EQ((*z)->frames.count, 2u);
  EXPECT_DOUBLE_EQ((*z)->frames.frame_time, 3.15e7);
  std::vector<Trs> pose(1);
  ASSERT_TRUE((ClipSamplingJob{z->get(), 3.15e7 / 2, WrapMode::kClamp, nullptr, pose, {}}.Run().ok()));
  EXPECT_NEAR(Eigen::AngleAxisd(pose[0].rotation).angle(), 0.5, 1e-12);  // the stored keys, slerped
}

// The packed form holds ranges and constants in float: a translation past
// 1e30 (a BVH channel of 2e79, found by fuzz/engine_compress_fuzz, decoded
// as infinity) is kept exact, and samples as stored.
TEST(CompressedClipTest, TranslationsPastFloatRangesAreKeptExactWithAWarning) {
  for (const double far : {2e79, 1e31}) {
    std::shared_ptr<Clip> clip = TwoKeys(1);
    clip->joints[0].translation.times = {0, 1};
    clip->joints[0].translation.values = {Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, far, 0)};
    StatusOr<std::shared_ptr<const CompressedClip>> z = CompressClip(clip);
    ASSERT_TRUE(z.ok()) << z.status().message();
    EXPECT_TRUE((*z)->exact()) << far;
    EXPECT_NE((*z)->warning.find("past the packed form's float ranges"), std::string::npos) << (*z)->warning;
    std::vector<Trs> pose(1);
    ASSERT_TRUE((ClipSamplingJob{z->get(), 1, WrapMode::kClamp, nullptr, pose, {}}.Run().ok()));
    EXPECT_EQ(pose[0].translation.y(), far);
  }
  std::shared_ptr<Clip> near = TwoKeys(1);  // within float ranges: lossy as usual
  near->joints[0].translation.times = {0, 1};
  near->joints[0].translation.values = {Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 50, 0)};
  StatusOr<std::shared_ptr<const CompressedClip>> z = CompressClip(near);
  ASSERT_TRUE(z.ok()) << z.status().message();
  EXPECT_FALSE((*z)->exact()) << (*z)->warning;
}

// Refinement chose segment 15 again after measuring segment 14, whose last
// frames interpolate toward 15's first samples: 14 went over the bound
// (1.07e-4 against 1e-4, at frames 237-239) while the clip claimed 9.98e-5.
// The segment before each one chosen again is now measured again. (Found
// by fuzz/engine_compress_fuzz.)
TEST(CompressedClipTest, TheSegmentBeforeOneChosenAgainIsMeasuredAgain) {
  constexpr std::string_view kBvh =
      "HIERARCHY\nROOT Hips\n{\n  OFFSET 5 0 0\n"
      "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
      "  JOINT Chest\n  {\n    OFFSET 0 5 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n"
      "    JOINT Neck\n    {\n      OFFSET 0 1 0\n      End Site\n      {\n        OFFSET 0 3 0\n      }\n"
      "    }\n  }\n}\nMOTION\nFrames: 3\nFrame Time: 5.0333333\n"
      "0 1 2 3 4 5 6 7 8\n1 2 9 4 1 6 7 8 9\n-1.5 +2 3e0 20 50 60 -70 80 90\n";
  StatusOr<BvhData> bvh = ParseBvh(kBvh, ImportLimits{});
  ASSERT_TRUE(bvh.ok()) << bvh.status().message();
  StatusOr<std::shared_ptr<const CompressedClip>> z = CompressClip(bvh->clip);
  ASSERT_TRUE(z.ok()) << z.status().message();
  ASSERT_FALSE((*z)->exact()) << (*z)->warning;
  ASSERT_GT((*z)->frames.count, 16u * 15) << "the clip no longer reaches segment 15";
  StatusOr<ClipError> measured =
      MeasureClipError(*bvh->clip, (*z)->frames, (*z)->bound.shell_distance, [&](double t, std::span<Trs> out) {
        return ClipSamplingJob{z->get(), t, WrapMode::kClamp, nullptr, out, {}}.Run();
      });
  ASSERT_TRUE(measured.ok()) << measured.status().message();
  EXPECT_LE(measured->worst, (*z)->bound.precision);
  EXPECT_DOUBLE_EQ(measured->worst, (*z)->error.worst) << "the clip's recorded error is not what it samples";
}

// A seek reads the next segment's header as far as the last track whose
// interval ends on it (a track of stride 2^k: at 2^k of a segment's 16
// frames), so the tracks doing so most often come first.
TEST(CompressedClipTest, TracksEndingOnTheNextSegmentMostOftenComeFirst) {
  SKIP_WITHOUT_SHARED_DATA();
  size_t ordered = 0;
  for (const test_util::SharedClip& c : Clips()) {
    auto z = CompressClip(c.clip);
    ASSERT_TRUE(z.ok()) << c.name;
    const CompressedClip& k = **z;
    if (k.exact()) continue;
    std::vector<size_t> weight(k.animated.size(), 0);
    for (const uint32_t offset : k.segment_offsets)
      for (size_t t = 0; t < k.animated.size(); ++t)
        weight[t] += size_t{1} << compression_internal::kCodes[k.data[offset + t]].stride_log;
    for (size_t t = 1; t < weight.size(); ++t)
      EXPECT_GE(weight[t - 1], weight[t]) << c.name << ": track " << t << " of " << weight.size();
    ordered += weight.size() > 1 && weight.front() > weight.back();
  }
  EXPECT_GT(ordered, 0u) << "no clip has tracks of different strides: the order was never tested";
}

TEST(CompressedClipTest, ExactKeepsTheStoredKeysBitForBit) {
  SKIP_WITHOUT_SHARED_DATA();
  ClipPrecision exact;
  exact.exact = true;
  for (const test_util::SharedClip& c : Clips()) {
    StatusOr<std::shared_ptr<const CompressedClip>> z = CompressClip(c.clip, exact);
    ASSERT_TRUE(z.ok()) << c.name;
    ASSERT_TRUE((*z)->exact());
    const Clip& kept = *(*z)->exact_keys;
    std::vector<Trs> ours(c.clip->skeleton->size()), stored(c.clip->skeleton->size());
    for (size_t j = 0; j < c.clip->joints.size(); ++j) {
      const JointTrack& a = c.clip->joints[j];
      const JointTrack& b = kept.joints[j];
      ASSERT_EQ(a.rotation.values.size(), b.rotation.values.size());
      for (size_t k = 0; k < a.rotation.values.size(); ++k)
        ASSERT_EQ(
            std::memcmp(a.rotation.values[k].coeffs().data(), b.rotation.values[k].coeffs().data(), 4 * sizeof(double)),
            0)
            << c.name;
      for (size_t k = 0; k < a.translation.values.size(); ++k)
        ASSERT_EQ(std::memcmp(a.translation.values[k].data(), b.translation.values[k].data(), 3 * sizeof(double)), 0);
      for (double t : a.rotation.times) {  // at each key time the job gives what SampleClip gives
        ASSERT_TRUE((ClipSamplingJob{z->get(), t, WrapMode::kClamp, nullptr, ours, {}}.Run().ok()));
        ASSERT_TRUE(SampleClip(*c.clip, t, {}, stored).ok());
        for (size_t i = 0; i < ours.size(); ++i) ASSERT_TRUE(SameBits(ours[i], stored[i])) << c.name << " t=" << t;
      }
    }
  }
}

TEST(CompressedClipTest, SequentialAndRandomSamplingAgree) {
  SKIP_WITHOUT_SHARED_DATA();
  for (const test_util::SharedClip& c : Clips()) {
    StatusOr<std::shared_ptr<const CompressedClip>> z = CompressClip(c.clip);
    ASSERT_TRUE(z.ok()) << c.name;
    const size_t n = c.clip->skeleton->size();
    std::vector<Trs> in_order(n), at_random(n);
    ClipSamplingContext context(**z);
    std::mt19937 rng(30);
    std::uniform_real_distribution<double> any(-0.5, c.clip->duration + 0.5);
    for (double t = 0; t <= c.clip->duration + 0.1; t += 1.0 / 90) {
      ASSERT_TRUE((ClipSamplingJob{z->get(), t, WrapMode::kLoop, &context, in_order, {}}.Run().ok()));
      ASSERT_TRUE((ClipSamplingJob{z->get(), t, WrapMode::kLoop, nullptr, at_random, {}}.Run().ok()));
      for (size_t i = 0; i < n; ++i) ASSERT_TRUE(SameBits(in_order[i], at_random[i])) << c.name << " t=" << t;
      const double r = any(rng);  // a jump away and back through the same context
      ASSERT_TRUE((ClipSamplingJob{z->get(), r, WrapMode::kClamp, &context, in_order, {}}.Run().ok()));
      ASSERT_TRUE((ClipSamplingJob{z->get(), r, WrapMode::kClamp, nullptr, at_random, {}}.Run().ok()));
      for (size_t i = 0; i < n; ++i) ASSERT_TRUE(SameBits(in_order[i], at_random[i])) << c.name << " t=" << r;
    }
  }
}

TEST(CompressedClipTest, JobValidatesItsInputs) {
  SKIP_WITHOUT_SHARED_DATA();
  StatusOr<std::shared_ptr<const CompressedClip>> z = CompressClip(Cmu());
  ASSERT_TRUE(z.ok());
  std::vector<Trs> small(3), pose(Cmu()->skeleton->size());
  EXPECT_FALSE((ClipSamplingJob{nullptr, 0, WrapMode::kClamp, nullptr, pose, {}}.Validate().ok()));
  EXPECT_FALSE((ClipSamplingJob{z->get(), 0, WrapMode::kClamp, nullptr, small, {}}.Validate().ok()));
  EXPECT_FALSE((ClipSamplingJob{z->get(), std::nan(""), WrapMode::kClamp, nullptr, pose, {}}.Validate().ok()));
  ClipSamplingContext other;
  EXPECT_FALSE((ClipSamplingJob{z->get(), 0, WrapMode::kClamp, &other, pose, {}}.Validate().ok()));
  EXPECT_TRUE((ClipSamplingJob{z->get(), 0, WrapMode::kClamp, nullptr, pose, {}}.Validate().ok()));
}

// By joint name onto a skeleton with the clip's joints in another order:
// each joint gets what its namesake gets on the clip's own skeleton.
TEST(CompressedClipTest, JointMapPlaysTheClipOnAnotherSkeleton) {
  SKIP_WITHOUT_SHARED_DATA();
  const std::shared_ptr<const Clip> cmu = Cmu();
  StatusOr<std::shared_ptr<const CompressedClip>> z = CompressClip(cmu);
  ASSERT_TRUE(z.ok());
  const Skeleton& source = *cmu->skeleton;
  Skeleton target;  // the clip's skeleton with one more joint and a longer bone the clip does not animate
  target = source;
  target.names.push_back("Prop");
  target.parents.push_back(0);
  target.rest.push_back(Trs{});
  target.channels.emplace_back();
  target.end_sites.emplace_back();
  std::vector<int> map;
  ASSERT_FALSE(MapJointsByName(target, source, "target", map).ok());  // "Prop" is not in the clip
  target = source;
  target.rest[3].translation *= 2;
  ASSERT_TRUE(MapJointsByName(target, source, "target", map).ok());
  ClipSamplingContext context(**z);
  std::vector<Trs> onto(target.size()), own(source.size());
  for (double t : {0.0, 0.5, 3.3, 20.0}) {
    ASSERT_TRUE((ClipSamplingOntoJob{z->get(), map, &target, t, WrapMode::kClamp, &context, onto, {}}.Run().ok()));
    ASSERT_TRUE((ClipSamplingJob{z->get(), t, WrapMode::kClamp, nullptr, own, {}}.Run().ok()));
    for (size_t j = 0; j < target.size(); ++j) {
      EXPECT_TRUE(onto[j].rotation.coeffs() == own[j].rotation.coeffs()) << j;
      const bool moves = !cmu->joints[j].translation.empty();
      EXPECT_TRUE(onto[j].translation == (moves ? own[j].translation : target.rest[j].translation)) << j;
    }
  }
  EXPECT_FALSE((ClipSamplingOntoJob{z->get(), map, &target, 0, WrapMode::kClamp, nullptr, onto, {}}.Validate().ok()));
}

}  // namespace
}  // namespace armature
