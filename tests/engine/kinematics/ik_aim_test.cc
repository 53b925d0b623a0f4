#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "armature/engine/kinematics/ik.h"
#include "../testing/ik_rigs.h"

namespace armature {
namespace {

using ik_rigs::WorldOf;

IkRequest AimRequest(const std::string& joint, const Eigen::Vector3d& target) {
  IkRequest r = ik_rigs::OneEffector(IkSolver::kAim, joint, target);
  r.effectors[0].aim_axis = Eigen::Vector3d::UnitZ();  // CMU faces +Z
  return r;
}

// From random body poses, the head's +Z points exactly at random targets.
TEST(IkAim, PointsTheAxisAtTheTarget) {
  const Skeleton s = ik_rigs::CmuLikeSkeleton();
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  IkWorkspace ws;
  IkResult result;
  for (int i = 0; i < 50; ++i) {
    std::vector<Trs> start = s.rest;
    for (const char* j : {"LowerBack", "Spine", "Neck1", "Head"})
      start[s.Find(j)].rotation = ExpQuaternion(Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.5);
    const Eigen::Vector3d target(20 * u(rng), 20 * u(rng), 20 * u(rng));
    IkRequest r = AimRequest("Head", target);
    r.start_pose = start;
    ASSERT_TRUE(SolveIk(s, r, ws, result).ok());
    EXPECT_TRUE(result.converged);
    const ik_rigs::World w = WorldOf(s, result.pose);
    const int head = s.Find("Head");
    const Eigen::Vector3d axis = w.rotation[head] * Eigen::Vector3d::UnitZ();
    EXPECT_GT(axis.dot((target - w.transform[head].translation()).normalized()), 1.0 - 1e-12);
    EXPECT_LT(result.residuals[0].rotation_error, 1e-6);
    EXPECT_LT(result.residuals[0].position_error, 1e-6);
    // Nothing but the head turned.
    for (size_t j = 0; j < s.size(); ++j)
      if (static_cast<int>(j) != head) EXPECT_TRUE(result.pose[j].rotation.isApprox(start[j].rotation));
  }
}

// With an up hint the roll is fixed: the joint's up axis lies in the plane of
// the aim direction and the hint, on the hint's side.
TEST(IkAim, UpHintFixesTheRoll) {
  const Skeleton s = ik_rigs::BuildSkeleton({{"rig", nullptr, {0, 0, 0}}, {"camera", "rig", {0, 2, 0}}});
  std::vector<Trs> start = s.rest;
  start[0].rotation = ExpQuaternion(Eigen::Vector3d(0.3, -0.2, 0.9));
  start[1].rotation = ExpQuaternion(Eigen::Vector3d(-1.0, 0.4, 0.2));
  const Eigen::Vector3d target(5, -1, 3), up(0, 1, 0);
  IkRequest r = AimRequest("camera", target);
  r.start_pose = start;
  r.effectors[0].aim_axis = -Eigen::Vector3d::UnitZ();  // cameras look down −Z
  r.effectors[0].up_axis = Eigen::Vector3d::UnitY();
  r.effectors[0].up_hint = up;
  IkWorkspace ws;
  IkResult result;
  ASSERT_TRUE(SolveIk(s, r, ws, result).ok());
  EXPECT_TRUE(result.converged);
  const ik_rigs::World w = WorldOf(s, result.pose);
  const Eigen::Quaterniond q = w.rotation[1];
  const Eigen::Vector3d forward = (target - w.transform[1].translation()).normalized();
  EXPECT_GT((q * -Eigen::Vector3d::UnitZ()).dot(forward), 1.0 - 1e-12);
  const Eigen::Vector3d camera_up = q * Eigen::Vector3d::UnitY();
  EXPECT_NEAR(camera_up.dot(forward.cross(up).normalized()), 0.0, 1e-12);  // no roll
  EXPECT_GT(camera_up.dot(up), 0.0);
  // Hand-derived: looking along f with up hint u, the camera's right axis is f × u.
  EXPECT_GT((q * Eigen::Vector3d::UnitX()).dot(forward.cross(up).normalized()), 1.0 - 1e-12);
}

// A target behind the head is out of its range: the head turns as far as
// its limit allows and reports the remaining angle.
TEST(IkAim, LimitedJointTurnsAsFarAsAllowed) {
  const Skeleton s = ik_rigs::CmuLikeSkeleton();
  const Eigen::Vector3d head = WorldOf(s, s.rest).Position(s, "Head");
  IkRequest r = AimRequest("Head", head + Eigen::Vector3d(10, 0, -10));  // back-left, 135° away
  r.limits = {ik_rigs::EulerLimit("Head", Eigen::Vector3d(-20, -60, -30), Eigen::Vector3d(20, 60, 30))};
  IkWorkspace ws;
  IkResult result;
  ASSERT_TRUE(SolveIk(s, r, ws, result).ok());
  EXPECT_FALSE(result.converged);
  EXPECT_EQ(result.stop, IkStop::kDone);
  EXPECT_TRUE(ik_rigs::WithinLimits(s, r.limits, result.pose));
  EXPECT_NEAR(result.residuals[0].rotation_error, (135.0 - 60.0) * std::numbers::pi / 180.0, 1e-6);
}

// Neck then head: the second aim corrects what the first left over.
TEST(IkAim, ChainedAimsEndOnTarget) {
  const Skeleton s = ik_rigs::CmuLikeSkeleton();
  const Eigen::Vector3d target(8, 30, 12);
  IkRequest r = AimRequest("Neck1", target);
  r.effectors.push_back(AimRequest("Head", target).effectors[0]);
  r.limits = {ik_rigs::EulerLimit("Neck1", Eigen::Vector3d(-10, -10, -10), Eigen::Vector3d(10, 10, 10))};
  IkWorkspace ws;
  IkResult result;
  ASSERT_TRUE(SolveIk(s, r, ws, result).ok());
  EXPECT_FALSE(result.residuals[0].reached);  // the neck alone cannot
  EXPECT_TRUE(result.residuals[1].reached);
  EXPECT_FALSE(result.converged);
  const ik_rigs::World w = WorldOf(s, result.pose);
  const int head = s.Find("Head");
  EXPECT_GT((w.rotation[head] * Eigen::Vector3d::UnitZ()).dot((target - w.transform[head].translation()).normalized()),
            1.0 - 1e-12);
}

}  // namespace
}  // namespace armature
