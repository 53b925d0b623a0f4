// The runtime form of clips against SampleClip (the file form, double
// precision, exact slerp) and against the exact slerp of math/rotation.h.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/compiled_clip.h"
#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/gltf/gltf.h"
#include "armature/engine/math/rotation.h"
#include "../testing/test_files.h"

namespace armature {
namespace {

double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const Eigen::Quaterniond d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

std::shared_ptr<Skeleton> Chain(size_t joints) {
  auto s = std::make_shared<Skeleton>();
  for (size_t i = 0; i < joints; ++i) {
    s->names.push_back("j" + std::to_string(i));
    s->parents.push_back(static_cast<int>(i) - 1);
    Trs rest;
    rest.translation = Eigen::Vector3d(0.5 * static_cast<double>(i), 1, -2);
    s->rest.push_back(rest);
  }
  s->channels.resize(joints);
  s->end_sites.resize(joints);
  return s;
}

Eigen::Quaterniond RandomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized();
}

// A chain of `joints` with a random rotation track at `times` on every joint.
std::shared_ptr<Clip> RandomRotationClip(size_t joints, const std::vector<double>& times, unsigned seed) {
  auto clip = std::make_shared<Clip>();
  clip->skeleton = Chain(joints);
  clip->joints.resize(joints);
  clip->duration = times.back();
  std::mt19937 rng(seed);
  for (JointTrack& jt : clip->joints) {
    jt.rotation.times = times;
    for (size_t k = 0; k < times.size(); ++k) jt.rotation.values.push_back(RandomRotation(rng));
  }
  return clip;
}

// Every joint's pose from both forms agrees: rotations within `radians`,
// translations and scales within `relative` of their size (at least 1).
void ExpectSamePose(const CompiledClip& compiled, double time, const SampleOptions& options, double radians,
                    double relative) {
  const Clip& clip = *compiled.source;
  std::vector<Trs> want(clip.skeleton->size()), got(clip.skeleton->size());
  ASSERT_TRUE(SampleClip(clip, time, options, want).ok());
  ASSERT_TRUE(SampleCompiledClip(compiled, time, options, got).ok());
  for (size_t j = 0; j < want.size(); ++j) {
    SCOPED_TRACE("joint " + clip.skeleton->names[j] + " at t = " + std::to_string(time));
    EXPECT_LE(AngleBetween(want[j].rotation, got[j].rotation), radians);
    EXPECT_LE((want[j].translation - got[j].translation).norm(), relative * std::max(1.0, want[j].translation.norm()));
    EXPECT_LE((want[j].scale - got[j].scale).norm(), relative * std::max(1.0, want[j].scale.norm()));
  }
}

// The stated bound of the trig-free slerp (src/anim/fast_slerp.h): at most
// 1e-6 rad from the exact slerp for any two keys and any time between them,
// float keys included. Pairs within 1e-4 of 180° apart are left out: there
// the shortest arc flips with the last bit of the dot product.
TEST(CompiledClipTest, FastSlerpIsWithinTheStatedBound) {
  auto clip = std::make_shared<Clip>();
  clip->skeleton = Chain(1);
  clip->joints.resize(1);
  clip->duration = 1;
  clip->frame_time = 1;
  QuatTrack& track = clip->joints[0].rotation;
  track.times = {0, 1};
  std::mt19937 rng(7);
  double worst = 0;
  for (int pair = 0; pair < 400; ++pair) {
    Eigen::Quaterniond a = RandomRotation(rng), b = RandomRotation(rng);
    if (pair % 4 == 1) b = Eigen::Quaterniond(a.coeffs() + 0.01 * b.coeffs()).normalized();  // small arcs
    if (pair % 4 == 2) b = Eigen::Quaterniond(-b.coeffs());                                  // the other hemisphere
    if (std::abs(a.dot(b)) < 1e-4) continue;
    track.values = {a, b};
    auto compiled = CompileClip(clip);
    ASSERT_TRUE(compiled.ok()) << compiled.status().message();
    ASSERT_TRUE((*compiled)->fallback_joints.empty());
    std::vector<Trs> pose(1);
    for (int i = 0; i <= 64; ++i) {
      const double t = i / 64.0;
      ASSERT_TRUE(SampleCompiledClip(**compiled, t, {}, pose).ok());
      const Eigen::Quaterniond exact = Slerp(a, b, t);
      worst = std::max(worst, AngleBetween(exact, pose[0].rotation));
      EXPECT_NEAR(pose[0].rotation.norm(), 1.0, 1e-6);
    }
  }
  EXPECT_LE(worst, 1e-6);
  std::cout << "fast slerp: worst " << worst << " rad from the exact slerp\n";
}

// Half a turn about one axis between two keys: the slerp's angle grows at a
// constant rate (nlerp would lag at the ends and lead in the middle by 0.07 rad).
TEST(CompiledClipTest, LinearRotationKeepsConstantAngularSpeed) {
  auto clip = std::make_shared<Clip>();
  clip->skeleton = Chain(1);
  clip->joints.resize(1);
  clip->duration = 2;
  QuatTrack& track = clip->joints[0].rotation;
  track.times = {0, 2};
  const double total = 0.9 * std::numbers::pi;
  track.values = {Eigen::Quaterniond::Identity(),
                  Eigen::Quaterniond(Eigen::AngleAxisd(total, Eigen::Vector3d::UnitY()))};
  auto compiled = CompileClip(clip);
  ASSERT_TRUE(compiled.ok());
  std::vector<Trs> pose(1);
  for (int i = 0; i <= 20; ++i) {
    const double t = 0.1 * i;
    ASSERT_TRUE(SampleCompiledClip(**compiled, t, {}, pose).ok());
    EXPECT_NEAR(AngleBetween(Eigen::Quaterniond::Identity(), pose[0].rotation), total * t / 2, 1e-6) << t;
  }
}

TEST(CompiledClipTest, MatchesSampleClipOnTheCmuClip) {
  const std::string file = test_util::SharedData("bvh/cmu_01_01.bvh").string();
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "shared data " << file << " is absent";
  std::ifstream in(file, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto bvh = ParseBvh(text);
  ASSERT_TRUE(bvh.ok()) << bvh.status().message();
  auto compiled = CompileClip(bvh->clip);
  ASSERT_TRUE(compiled.ok()) << compiled.status().message();
  const CompiledClip& c = **compiled;
  EXPECT_TRUE(c.fallback_joints.empty()) << "every BVH track is uniform";
  const size_t linear_bytes = c.KeyBytes();
  EXPECT_EQ(c.RotationControls().size(), c.rotations.keys.size()) << "CUBIC is compiled";
  EXPECT_EQ(c.KeyBytes(), linear_bytes + c.rotations.keys.size() * sizeof(float)) << "control points on first use";
  EXPECT_EQ(c.times.size(), bvh->clip->frame_count);
  const double d = bvh->clip->duration;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> any(-0.5, d + 0.5);
  std::vector<double> times = {0, d, -1, d + 1, c.times[1], c.times[100], c.times[100] - 1e-12, 0.5004, 11.1};
  for (int i = 0; i < 200; ++i) times.push_back(any(rng));
  for (double t : times) {
    ExpectSamePose(c, t, {}, 1e-6, 1e-6);
    ExpectSamePose(c, t, {.interpolation = Interpolation::kStep}, 1e-6, 1e-6);
    ExpectSamePose(c, 3 * d + t, {.wrap = WrapMode::kLoop}, 1e-6, 1e-6);
    ExpectSamePose(c, t, {.interpolation = Interpolation::kCubic}, 1e-6, 1e-6);
  }
}

// glTF clips: channels sharing one set of key times are compiled, the rest
// sampled from the source; either way the poses are SampleClip's.
TEST(CompiledClipTest, MatchesSampleClipOnRobotExpressive) {
  const std::string file = test_util::SharedData("gltf/RobotExpressive/RobotExpressive.glb").string();
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "shared data " << file << " is absent";
  std::ifstream in(file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto asset = ParseGltf(bytes, true, "robot");
  ASSERT_TRUE(asset.ok()) << asset.status().message();
  ASSERT_FALSE(asset->clips.empty());
  for (const NamedClip& named : asset->clips) {
    SCOPED_TRACE(named.name);
    auto compiled = CompileClip(named.clip);
    ASSERT_TRUE(compiled.ok()) << compiled.status().message();
    const CompiledClip& c = **compiled;
    std::cout << named.name << ": " << c.times.size() << " keys, " << c.rotations.joints.size() << " rotation and "
              << c.translations.joints.size() << " translation tracks compiled, " << c.fallback_joints.size()
              << " joints from the source\n";
    const double d = named.clip->duration;
    for (int i = -2; i <= 42; ++i) {
      const double t = d * i / 40.0;
      ExpectSamePose(c, t, {}, 1e-6, 1e-6);
      ExpectSamePose(c, t, {.interpolation = Interpolation::kStep}, 1e-6, 1e-6);
      ExpectSamePose(c, t, {.interpolation = Interpolation::kCubic}, 1e-6, 1e-6);
    }
  }
}

// Tracks outside the uniform group (uneven times, a single key, CUBIC) are
// sampled from the source; STEP and per-track interpolation are kept.
TEST(CompiledClipTest, MixedTracksMatchSampleClip) {
  const std::vector<double> even = {0, 0.3, 0.6, 0.9, 1.2};
  std::shared_ptr<Clip> clip = RandomRotationClip(6, even, 11);
  clip->joints[2] = RandomRotationClip(1, {0, 0.1, 1.0}, 12)->joints[0];
  for (size_t j = 0; j < 6; ++j) {
    JointTrack& jt = clip->joints[j];
    if (j == 1) jt.rotation.interpolation = Interpolation::kStep;
    if (j == 3) jt.rotation.interpolation = Interpolation::kCubic;
    if (j == 0 || j == 4) {
      jt.translation.times = even;
      jt.scale.times = even;
      for (size_t k = 0; k < even.size(); ++k) {
        jt.translation.values.push_back(Eigen::Vector3d::Random() * 50);
        jt.scale.values.push_back(Eigen::Vector3d::Ones() + 0.5 * Eigen::Vector3d::Random());
      }
      if (j == 4) jt.translation.interpolation = Interpolation::kStep;
    }
    if (j == 5) {
      jt.rotation.times = {0.4};
      jt.rotation.values.resize(1);
    }
  }
  auto compiled = CompileClip(clip);
  ASSERT_TRUE(compiled.ok()) << compiled.status().message();
  EXPECT_EQ((*compiled)->fallback_joints, (std::vector<uint32_t>{2, 3, 5}));
  for (double t = -0.2; t < 1.5; t += 0.0125) {
    ExpectSamePose(**compiled, t, {}, 1e-6, 1e-6);
    ExpectSamePose(**compiled, t, {.interpolation = Interpolation::kLinear}, 1e-6, 1e-6);
    ExpectSamePose(**compiled, t, {.interpolation = Interpolation::kStep}, 1e-6, 1e-6);
    ExpectSamePose(**compiled, t, {.interpolation = Interpolation::kCubic}, 1e-6, 1e-6);
  }
  for (double key : even) ExpectSamePose(**compiled, key, {}, 1e-6, 1e-6);
}

// Keys 25 % off even spacing still share one group (direct indexing plus one
// correcting step), but squad's in and out control points differ there, so
// CUBIC samples the source.
TEST(CompiledClipTest, UnevenTimesKeepDirectIndexingAndSampleCubicFromTheSource) {
  std::shared_ptr<Clip> clip = RandomRotationClip(2, {0, 0.2, 0.45, 0.6, 0.8, 1.0}, 2);
  auto compiled = CompileClip(clip);
  ASSERT_TRUE(compiled.ok());
  EXPECT_TRUE((*compiled)->fallback_joints.empty());
  EXPECT_TRUE((*compiled)->RotationControls().empty());
  for (double t = 0; t <= 1.0; t += 0.01) {
    ExpectSamePose(**compiled, t, {}, 1e-6, 1e-6);
    ExpectSamePose(**compiled, t, {.interpolation = Interpolation::kCubic}, 0, 0);
  }
  for (double key : clip->joints[0].rotation.times)
    ExpectSamePose(**compiled, key, {.interpolation = Interpolation::kStep}, 1e-6, 1e-6);
}

// The control points are computed on the first CUBIC sample, once, even when
// several threads ask at the same time (a shared clip in the server).
TEST(CompiledClipTest, ConcurrentFirstCubicSamplesAgree) {
  std::vector<double> times;
  for (int k = 0; k <= 20; ++k) times.push_back(0.1 * k);
  std::shared_ptr<Clip> clip = RandomRotationClip(5, times, 9);
  auto compiled = CompileClip(clip);
  ASSERT_TRUE(compiled.ok());
  const size_t before = (*compiled)->KeyBytes();
  std::vector<std::thread> threads;
  std::vector<std::vector<Trs>> poses(4, std::vector<Trs>(5));
  for (size_t i = 0; i < 4; ++i)
    threads.emplace_back([&, i] {
      EXPECT_TRUE(SampleCompiledClip(**compiled, 0.77, {.interpolation = Interpolation::kCubic}, poses[i]).ok());
    });
  for (std::thread& t : threads) t.join();
  EXPECT_GT((*compiled)->KeyBytes(), before);
  for (size_t i = 1; i < 4; ++i)
    for (size_t j = 0; j < 5; ++j) EXPECT_EQ(poses[i][j].rotation.coeffs(), poses[0][j].rotation.coeffs());
  ExpectSamePose(**compiled, 0.77, {.interpolation = Interpolation::kCubic}, 1e-6, 1e-6);
}

TEST(CompiledClipTest, RejectsWhatSampleClipRejects) {
  EXPECT_EQ(CompileClip(nullptr).status().code(), StatusCode::kInvalidArgument);
  auto bad = std::make_shared<Clip>();
  bad->skeleton = Chain(2);
  bad->joints.resize(1);
  const Status s = CompileClip(bad).status();
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("joint tracks"), std::string::npos) << s.message();

  auto clip = std::make_shared<Clip>();
  clip->skeleton = Chain(2);
  clip->joints.resize(2);
  auto compiled = CompileClip(clip);
  ASSERT_TRUE(compiled.ok());
  std::vector<Trs> small(1), pose(2);
  EXPECT_EQ(SampleCompiledClip(**compiled, 0, {}, small).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(SampleCompiledClip(**compiled, std::nan(""), {}, pose).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(SampleCompiledClip(**compiled, 0, {.wrap = static_cast<WrapMode>(7)}, pose).code(),
            StatusCode::kInvalidArgument);
  ASSERT_TRUE(SampleCompiledClip(**compiled, 0.3, {}, pose).ok());  // no tracks: the rest pose
  EXPECT_EQ(pose[1].translation, clip->skeleton->rest[1].translation);
}

}  // namespace
}  // namespace armature
