#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/io/demo_walk.h"
#include "armature/engine/math/rotation.h"
#include "../testing/bvh_reference.h"

namespace armature {
namespace {

constexpr int kFramesPerCycle = 30;  // 1 s cycle at 30 fps

double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const Eigen::Quaterniond d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

class DemoWalk : public ::testing::Test {
 protected:
  void SetUp() override {
    walk_ = MakeDemoWalk();
    ASSERT_TRUE(walk_.skeleton && walk_.clip);
  }
  const Skeleton& sk() const { return *walk_.skeleton; }
  size_t Joint(const std::string& name) const {
    const int j = sk().Find(name);
    EXPECT_GE(j, 0) << name;
    return static_cast<size_t>(std::max(j, 0));
  }
  const Eigen::Quaterniond& Rotation(const std::string& joint, int frame) const {
    return walk_.clip->joints[Joint(joint)].rotation.values[static_cast<size_t>(frame)];
  }
  Eigen::Vector3d Root(int frame) const { return walk_.clip->joints[0].translation.values[static_cast<size_t>(frame)]; }
  std::vector<Eigen::Vector3d> World(int frame) const {
    return testing::EnginePositionsAt(walk_, frame * kDemoWalkFrameTime);
  }
  BvhData walk_;
};

// Independent rotation from axis matrices (degrees), as a quaternion via Eigen.
Eigen::Quaterniond Expected(const std::string& axes, std::vector<double> degrees) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
  for (size_t i = 0; i < axes.size(); ++i) m = m * testing::RefAxisMatrix(axes[i], degrees[i]);
  return Eigen::Quaterniond(m);
}

TEST_F(DemoWalk, SkeletonAndClipShape) {
  EXPECT_TRUE(sk().Validate().ok());
  EXPECT_TRUE(walk_.clip->Validate().ok());
  const std::vector<std::string> names = {"Hips",      "LeftHip",       "LeftKnee",   "LeftAnkle",    "LeftToe",
                                          "RightHip",  "RightKnee",     "RightAnkle", "RightToe",     "Spine",
                                          "Chest",     "Neck",          "Head",       "LeftShoulder", "LeftElbow",
                                          "LeftWrist", "RightShoulder", "RightElbow", "RightWrist"};
  EXPECT_EQ(sk().names, names);
  EXPECT_EQ(sk().channels[0].size(), 6u);
  for (size_t j = 1; j < sk().size(); ++j) EXPECT_EQ(sk().channels[j].size(), 3u);
  for (const char* tip : {"LeftToe", "RightToe", "Head", "LeftWrist", "RightWrist"})
    EXPECT_TRUE(sk().end_sites[Joint(tip)].has_value()) << tip;
  EXPECT_EQ(walk_.clip->frame_count, static_cast<size_t>(kDemoWalkCycles * kFramesPerCycle + 1));
  EXPECT_NEAR(walk_.clip->frame_time, 1.0 / 30.0, 1e-15);
  EXPECT_NEAR(walk_.clip->duration, kDemoWalkCycles * kDemoWalkCycleSeconds, 1e-12);
  EXPECT_EQ(walk_.clip->default_interpolation, Interpolation::kLinear);
}

// Frames 0 and 15 fall on key phases 0 and 0.5: the keyed angles come out.
TEST_F(DemoWalk, KeyedAnglesAtKeyPhases) {
  // Left heel strike: hip flexed 25°, knee 3°, right hip extended 10°; both
  // hips yawed 5° against the pelvis.
  EXPECT_LT(AngleBetween(Rotation("LeftHip", 0), Expected("YX", {5, -25})), 1e-9);
  EXPECT_LT(AngleBetween(Rotation("LeftKnee", 0), Expected("X", {3})), 1e-9);
  EXPECT_LT(AngleBetween(Rotation("RightHip", 0), Expected("YX", {5, 10})), 1e-9);
  EXPECT_LT(AngleBetween(Rotation("Hips", 0), Expected("Y", {-5})), 1e-9);
  // Left arm back (opposite the left leg), abducted 6°.
  EXPECT_LT(AngleBetween(Rotation("LeftShoulder", 0), Expected("XZ", {15, 6})), 1e-9);
  EXPECT_LT(AngleBetween(Rotation("RightShoulder", 0), Expected("XZ", {-15, -6})), 1e-9);
  // Half a cycle later the sides swap.
  EXPECT_LT(AngleBetween(Rotation("LeftHip", 15), Expected("YX", {-5, 10})), 1e-9);
  EXPECT_LT(AngleBetween(Rotation("LeftKnee", 15), Expected("X", {8})), 1e-9);
  EXPECT_LT(AngleBetween(Rotation("RightHip", 15), Expected("YX", {-5, -25})), 1e-9);
  EXPECT_LT(AngleBetween(Rotation("Hips", 15), Expected("Y", {5})), 1e-9);
}

// Reflection across the body's midplane (x → −x) keeps rotations about X
// and reverses those about Y and Z.
Eigen::Quaterniond Mirror(const Eigen::Quaterniond& q) { return Eigen::Quaterniond(q.w(), q.x(), -q.y(), -q.z()); }

TEST_F(DemoWalk, RightSideIsTheMirroredLeftHalfACycleLater) {
  for (int f = 0; f + 15 <= kDemoWalkCycles * kFramesPerCycle; ++f)
    for (const char* j : {"Hip", "Knee", "Ankle", "Toe", "Shoulder", "Elbow"})
      EXPECT_LT(AngleBetween(Rotation(std::string("Right") + j, f), Mirror(Rotation(std::string("Left") + j, f + 15))),
                1e-9)
          << j << " frame " << f;
}

TEST_F(DemoWalk, RootAdvancesAtWalkingSpeedAndBobs) {
  double low = 1e9, high = -1e9;
  for (int f = 0; f <= kDemoWalkCycles * kFramesPerCycle; ++f) {
    // Keys on a straight line at even spacing: cubic sampling reproduces it.
    EXPECT_NEAR(Root(f).z(), kDemoWalkSpeed * f * kDemoWalkFrameTime, 1e-9) << f;
    low = std::min(low, Root(f).y());
    high = std::max(high, Root(f).y());
  }
  EXPECT_NEAR(low, kDemoWalkHipHeight - 1.5, 1e-9);  // double support, keyed
  EXPECT_GT(high, kDemoWalkHipHeight + 1.4);         // mid-stance, between frames of the key
  EXPECT_LE(high, kDemoWalkHipHeight + 1.5 + 1e-9);
}

TEST_F(DemoWalk, LoopsSeamlessly) {
  const int last = kDemoWalkCycles * kFramesPerCycle;
  for (size_t j = 0; j < sk().size(); ++j) {
    const std::string& name = sk().names[j];
    EXPECT_LT(AngleBetween(Rotation(name, 0), Rotation(name, last)), 1e-9) << name;
    // Angular velocity across the seam (last-1 → last ≡ 0, then 0 → 1)
    // changes exactly as much as across frame 30 inside the clip.
    auto step = [&](int f) { return LogQuaternion(Rotation(name, f).conjugate() * Rotation(name, f + 1)); };
    const double seam = (step(last - 1) - step(0)).norm();
    const double inside = (step(29) - step(30)).norm();
    EXPECT_NEAR(seam, inside, 1e-9) << name;
  }
  EXPECT_NEAR(Root(last).y(), Root(0).y(), 1e-9);
}

TEST_F(DemoWalk, JointAnglesStayAnatomical) {
  double knee_max = 0;
  for (int f = 0; f <= kDemoWalkCycles * kFramesPerCycle; ++f) {
    for (const char* side : {"Left", "Right"}) {
      // Knee flexes about +X only, between straight and ~65°.
      const Eigen::Vector3d knee = LogQuaternion(Rotation(std::string(side) + "Knee", f));
      EXPECT_NEAR(knee.y(), 0, 1e-12);
      EXPECT_NEAR(knee.z(), 0, 1e-12);
      EXPECT_GE(knee.x(), 0.0) << side << " frame " << f;
      EXPECT_LE(knee.x(), 66 * std::numbers::pi / 180) << side << " frame " << f;
      knee_max = std::max(knee_max, knee.x());
      // Elbow flexion (−X) stays within its keyed 10°…25° (± overshoot).
      const double elbow = -LogQuaternion(Rotation(std::string(side) + "Elbow", f)).x() * 180 / std::numbers::pi;
      EXPECT_GT(elbow, 9.0);
      EXPECT_LT(elbow, 26.0);
    }
  }
  EXPECT_GT(knee_max, 55 * std::numbers::pi / 180);  // swing phase
}

// The speed matches the stride: over mid-stance the stance foot's ball stays
// within 5 cm of where it was and near the ground while the body moves 30 cm
// (a speed off by 20% would drag it 7 cm).
TEST_F(DemoWalk, StanceFootStaysPlanted) {
  const size_t left_toe = Joint("LeftToe"), right_toe = Joint("RightToe");
  for (int cycle = 0; cycle < kDemoWalkCycles; ++cycle) {
    for (auto [toe, first, last] : {std::tuple{left_toe, 4, 13}, std::tuple{right_toe, 19, 28}}) {
      const int f0 = cycle * kFramesPerCycle + first, f1 = cycle * kFramesPerCycle + last;
      const Eigen::Vector3d start = World(f0)[toe];
      for (int f = f0; f <= f1; ++f) {
        const Eigen::Vector3d p = World(f)[toe];
        EXPECT_LT(std::hypot(p.x() - start.x(), p.z() - start.z()), 5.0) << "frame " << f;
        EXPECT_LT(std::abs(p.y()), 3.0) << "frame " << f;
      }
      EXPECT_GT(Root(f1).z() - Root(f0).z(), 30.0);
    }
  }
}

// No foot point goes below the floor (y = 0): the ankles, the balls of the
// feet (the toe joints) and the toe tips, over the whole clip sampled four
// times a frame (the keyed ankle and toe alone went 3.5 and 4.5 cm below at
// toe-off).
TEST_F(DemoWalk, FeetStayAboveTheFloor) {
  std::vector<Trs> local(sk().size());
  std::vector<Eigen::Affine3d> world(sk().size());
  double lowest = 1e9;
  std::string where;
  for (int s = 0; s <= 4 * kDemoWalkCycles * kFramesPerCycle; ++s) {
    const double t = s * kDemoWalkFrameTime / 4;
    ASSERT_TRUE(SampleClip(*walk_.clip, t, {}, local).ok());
    ComputeWorld(sk(), local, world);
    for (const std::string side : {"Left", "Right"}) {
      const size_t ankle = Joint(side + "Ankle"), toe = Joint(side + "Toe");
      const std::pair<std::string, double> points[] = {{"Ankle", world[ankle].translation().y()},
                                                       {"Toe", world[toe].translation().y()},
                                                       {"Toe tip", (world[toe] * *sk().end_sites[toe]).y()}};
      for (const auto& [name, y] : points)
        if (y < lowest) {
          lowest = y;
          where = side + name + " at t = " + std::to_string(t);
        }
    }
  }
  EXPECT_GE(lowest, -0.5) << where;
}

TEST_F(DemoWalk, WriteThenReadKeepsJointsAndPoses) {
  const BvhData back = testing::ParseExpectOk(WriteBvh(*walk_.clip));
  ASSERT_TRUE(back.clip);
  EXPECT_EQ(back.skeleton->names, sk().names);
  EXPECT_EQ(back.skeleton->parents, sk().parents);
  EXPECT_EQ(back.skeleton->channels, sk().channels);
  EXPECT_EQ(back.clip->frame_count, walk_.clip->frame_count);
  for (int f = 0; f <= kDemoWalkCycles * kFramesPerCycle; ++f)
    EXPECT_LT(testing::MaxDistance(testing::EnginePositionsAt(back, f * kDemoWalkFrameTime), World(f)), 1e-4) << f;
}

}  // namespace
}  // namespace armature
