// The crowd's pose encoding (issue 31): smallest-three rotations stay within
// the stated bound on random and worst-case rotations and on every real clip
// of ../shared/data, translations round to float, and CMU and RobotExpressive
// poses cost at most 8 bytes a joint.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/crowd/pose_encoding.h"
#include "../../testing/shared_clips.h"

namespace armature {
namespace {

double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const double dot = std::min(1.0, std::abs(a.normalized().dot(b.normalized())));
  return 2 * std::acos(dot);
}

const std::vector<test_util::SharedClip>& Clips() {
  static const std::vector<test_util::SharedClip> clips = test_util::LoadSharedClips();
  return clips;
}

TEST(PoseEncodingTest, TheStatedBoundIsFourArcsinesOfRootThreeE) {
  const double e = std::sqrt(2.0) / (2 * 32767.0);
  EXPECT_NEAR(MaxEncodedRotationError(), 4 * std::asin(std::sqrt(3.0) * e), 1e-15);
  EXPECT_NEAR(MaxEncodedRotationError(), 1.495e-4, 1e-6);  // 0.0086°
}

TEST(PoseEncodingTest, RandomRotationsRoundTripWithinTheBound) {
  std::mt19937_64 rng(31);
  std::normal_distribution<double> n;
  double worst = 0;
  for (int i = 0; i < 200000; ++i) {
    Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
    q.normalize();
    const uint64_t bits = EncodeRotation(q);
    ASSERT_LT(bits, uint64_t{1} << 47);  // 2 + 3 × 15 bits
    worst = std::max(worst, AngleBetween(q, DecodeRotation(bits)));
  }
  EXPECT_LE(worst, MaxEncodedRotationError());
  EXPECT_GT(worst, 0.25 * MaxEncodedRotationError());  // the bound is not loose by more than 4×
}

// The crowd's float path quantizes as the double one: the same bits for
// the same (float) rotation, q and −q alike.
TEST(PoseEncodingTest, FloatRotationsEncodeAsTheirDoubleValues) {
  std::mt19937_64 rng(37);
  std::normal_distribution<double> n;
  for (int i = 0; i < 200000; ++i) {
    Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
    q.normalize();
    const float f[4] = {static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()),
                        static_cast<float>(q.w())};
    const Eigen::Quaterniond same(f[3], f[0], f[1], f[2]);
    ASSERT_EQ(EncodeRotation(f), EncodeRotation(same)) << i;
  }
  const float edge[4] = {0.5f, -0.5f, 0.5f, -0.5f};  // ties: the first largest, as the double path
  EXPECT_EQ(EncodeRotation(edge), EncodeRotation(Eigen::Quaterniond(-0.5, 0.5, -0.5, 0.5)));
}

TEST(PoseEncodingTest, TheWorstCaseRotationsStayWithinTheBound) {
  // Largest component 1/2 with the other three at a half step off the grid.
  const double step = std::sqrt(2.0) / 32767, half = step / 2;
  for (double dx : {-half, half})
    for (double dy : {-half, half}) {
      Eigen::Quaterniond q(0.5, 0.5 + dx, 0.5 + dy, 0.5 - dx);
      q.normalize();
      EXPECT_LE(AngleBetween(q, DecodeRotation(EncodeRotation(q))), MaxEncodedRotationError());
    }
  const Eigen::Quaterniond identity = Eigen::Quaterniond::Identity();
  EXPECT_LT(AngleBetween(identity, DecodeRotation(EncodeRotation(identity))), 1e-4);
  const Eigen::Quaterniond negated(-0.3, 0.1, -0.9, 0.2);  // q and −q: one rotation
  EXPECT_LE(AngleBetween(negated.normalized(), DecodeRotation(EncodeRotation(negated.normalized()))),
            MaxEncodedRotationError());
}

TEST(PoseEncodingTest, RealPosesRoundTripWithinTheBoundInAtMostEightBytesAJoint) {
  if (Clips().empty()) GTEST_SKIP() << "../shared/data is absent";
  int checked = 0;
  for (const test_util::SharedClip& shared : Clips()) {
    StatusOr<std::shared_ptr<const CompressedClip>> clip = CompressClip(shared.clip);
    ASSERT_TRUE(clip.ok()) << shared.name << ": " << clip.status().message();
    StatusOr<PoseLayout> layout = LayoutOfClip(**clip);
    ASSERT_TRUE(layout.ok()) << shared.name;
    const bool cmu_or_robot = shared.name.find("cmu_01_01") != std::string::npos ||
                              shared.name.find("RobotExpressive.glb#") != std::string::npos;
    const double per_joint = static_cast<double>(layout->EncodedSize()) / layout->joints;
    if (cmu_or_robot) EXPECT_LE(per_joint, 8.0) << shared.name << ": " << layout->translated.size() << " translated";
    std::vector<Trs> pose(layout->joints), decoded(layout->joints);
    std::vector<uint8_t> bytes(layout->EncodedSize());
    for (int k = 0; k <= 12; ++k) {
      const double t = (*clip)->duration * k / 12;
      ASSERT_TRUE((ClipSamplingJob{clip->get(), t, WrapMode::kClamp, nullptr, pose, std::nullopt}.Run().ok()));
      EncodePose(*layout, pose, bytes.data());
      ASSERT_TRUE(DecodePose(*layout, bytes, decoded).ok());
      for (size_t j = 0; j < pose.size(); ++j) {
        ASSERT_LE(AngleBetween(pose[j].rotation, decoded[j].rotation), MaxEncodedRotationError())
            << shared.name << " joint " << j << " t " << t;
        const double scale = std::max(1.0, pose[j].translation.norm());
        ASSERT_LE((pose[j].translation - decoded[j].translation).norm(), 1e-6 * scale) << shared.name << " " << j;
        ASSERT_LE((pose[j].scale - decoded[j].scale).norm(), 1e-6 * pose[j].scale.norm()) << shared.name << " " << j;
      }
    }
    ++checked;
  }
  EXPECT_GE(checked, 3);
}

TEST(PoseEncodingTest, CmuPosesAre6Point4BytesAJoint) {
  if (Clips().empty()) GTEST_SKIP() << "../shared/data is absent";
  for (const test_util::SharedClip& shared : Clips()) {
    if (shared.name != "bvh/cmu_01_01.bvh") continue;
    auto clip = CompressClip(shared.clip);
    ASSERT_TRUE(clip.ok());
    auto layout = LayoutOfClip(**clip);
    ASSERT_TRUE(layout.ok());
    EXPECT_EQ(layout->joints, 31u);
    EXPECT_EQ(layout->translated.size(), 1u);  // the hips only
    EXPECT_EQ(layout->EncodedSize(), 31u * 6 + 12);
    return;
  }
  FAIL() << "no CMU clip";
}

TEST(PoseEncodingTest, WrongSizesAreRefused) {
  PoseLayout layout;
  layout.joints = 2;
  layout.base.resize(2);
  std::vector<uint8_t> bytes(11);
  std::vector<Trs> pose(2);
  EXPECT_FALSE(DecodePose(layout, bytes, pose).ok());
  bytes.resize(12);
  EXPECT_TRUE(DecodePose(layout, bytes, pose).ok());
  std::vector<Trs> small(1);
  EXPECT_FALSE(DecodePose(layout, bytes, small).ok());
}

}  // namespace
}  // namespace armature
