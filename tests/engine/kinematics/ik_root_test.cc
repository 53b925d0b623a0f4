// The skeleton root (the hips) stays where it stands unless freed: reaching
// with a hand never swings the legs. Checked on the CMU-like body from a
// pose that is not the rest pose, by the engine's forward kinematics.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "armature/engine/kinematics/ik.h"
#include "armature/engine/math/rotation.h"
#include "../testing/ik_rigs.h"

namespace armature {
namespace {

using ik_rigs::WorldOf;

// A standing pose, turned and shifted: hips yawed 30° and raised, elbows bent.
std::vector<Trs> StartPose(const Skeleton& s) {
  std::vector<Trs> pose = s.rest;
  pose[s.Find("Hips")].translation = Eigen::Vector3d(1, 17, -2);
  pose[s.Find("Hips")].rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.5236, Eigen::Vector3d::UnitY()));
  pose[s.Find("LeftForeArm")].rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()));
  return pose;
}

const char* const kLegJoints[] = {"LeftUpLeg",  "LeftLeg",  "LeftFoot",  "LeftToeBase",
                                  "RightUpLeg", "RightLeg", "RightFoot", "RightToeBase"};

// A hand target in reach of spine and arm: the hand's start position moved
// 3 units forward and 2 up (a bone of the arm is 3.5 to 5).
IkRequest HandReach(const Skeleton& s, const std::vector<Trs>& start, IkSolver solver) {
  const Eigen::Vector3d hand = WorldOf(s, start).Position(s, "LeftHand");
  IkRequest r = ik_rigs::OneEffector(solver, "LeftHand", hand + Eigen::Vector3d(0, 2, 3));
  r.start_pose = start;
  r.options.max_iterations = 1000;
  return r;
}

TEST(IkRoot, ByDefaultTheHipsAndLegsStayWhereTheyStand) {
  const Skeleton s = ik_rigs::CmuLikeSkeleton();
  const std::vector<Trs> start = StartPose(s);
  const ik_rigs::World before = WorldOf(s, start);
  for (const IkSolver solver : {IkSolver::kDls, IkSolver::kCcd, IkSolver::kFabrik}) {
    IkWorkspace ws;
    IkResult result;
    const IkRequest r = HandReach(s, start, solver);
    ASSERT_TRUE(SolveIk(s, r, ws, result).ok());
    EXPECT_TRUE(result.converged) << static_cast<int>(solver);
    const ik_rigs::World after = WorldOf(s, result.pose);
    EXPECT_LE((after.Position(s, "LeftHand") - *r.effectors[0].target_position).norm(), ws.position_tolerance + 1e-12);
    // The root's local transform is untouched, so everything hanging from it
    // but the moved chain is bit for bit where it was.
    const int hips = s.Find("Hips");
    EXPECT_EQ(result.pose[hips].translation, start[hips].translation);
    EXPECT_EQ(result.pose[hips].rotation.coeffs(), start[hips].rotation.coeffs());
    EXPECT_LE((after.Position(s, "Hips") - before.Position(s, "Hips")).norm(), 1e-9);
    EXPECT_LE(after.rotation[hips].angularDistance(before.rotation[hips]), 1e-9);
    for (const char* leg : kLegJoints)
      EXPECT_LE((after.Position(s, leg) - before.Position(s, leg)).norm(), 1e-9) << leg;
    // And the arm did the work: the spine or shoulder turned.
    EXPECT_GT(result.pose[s.Find("LeftArm")].rotation.angularDistance(start[s.Find("LeftArm")].rotation), 1e-3);
  }
}

// Out of reach of spine and arm while the hips stand still; reachable once
// the hips may move. Each freedom moves the root as asked and no more.
TEST(IkRoot, FreeRootLetsTheHipsTurnAndMove) {
  const Skeleton s = ik_rigs::CmuLikeSkeleton();
  const std::vector<Trs> start = StartPose(s);
  const int hips = s.Find("Hips");
  const Eigen::Vector3d hand = WorldOf(s, start).Position(s, "LeftHand");
  IkRequest r = HandReach(s, start, IkSolver::kDls);
  r.effectors[0].target_position = hand + Eigen::Vector3d(0, -14, 20);  // the spine's reach is about 4 + 12
  IkWorkspace ws;
  IkResult fixed, translated, both;
  ASSERT_TRUE(SolveIk(s, r, ws, fixed).ok());
  EXPECT_FALSE(fixed.converged);
  EXPECT_EQ(fixed.pose[hips].translation, start[hips].translation);
  EXPECT_EQ(fixed.pose[hips].rotation.coeffs(), start[hips].rotation.coeffs());

  r.free_root_translation = true;
  ASSERT_TRUE(SolveIk(s, r, ws, translated).ok());
  EXPECT_TRUE(translated.converged);
  EXPECT_GT((translated.pose[hips].translation - start[hips].translation).norm(), 1.0);
  EXPECT_EQ(translated.pose[hips].rotation.coeffs(), start[hips].rotation.coeffs());  // moved, not turned

  r.free_root_rotation = true;
  ASSERT_TRUE(SolveIk(s, r, ws, both).ok());
  EXPECT_TRUE(both.converged);
  EXPECT_GT((both.pose[hips].translation - start[hips].translation).norm(), 1.0);

  // Rotation alone: the hips join the free joints; their translation stays.
  auto hips_free = [&] {
    return std::find(ws.free_joints.begin(), ws.free_joints.end(), hips) != ws.free_joints.end();
  };
  IkRequest turn = HandReach(s, start, IkSolver::kDls);
  IkResult turned;
  ASSERT_TRUE(SolveIk(s, turn, ws, turned).ok());
  EXPECT_FALSE(hips_free());
  turn.free_root_rotation = true;
  ASSERT_TRUE(SolveIk(s, turn, ws, turned).ok());
  EXPECT_TRUE(hips_free());
  EXPECT_TRUE(turned.converged);
  EXPECT_EQ(turned.pose[hips].translation, start[hips].translation);
}

TEST(IkRoot, FreeRootRotationIsRefusedByTheOneShotSolvers) {
  const Skeleton s = ik_rigs::CmuLikeSkeleton();
  IkWorkspace ws;
  IkResult result;
  IkRequest r = ik_rigs::OneEffector(IkSolver::kTwoBone, "LeftFoot", Eigen::Vector3d(2, -12, 1));
  r.free_root_rotation = true;
  Status st = SolveIk(s, r, ws, result);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message(), "free_root_rotation: the two-bone solver turns fixed joints; use dls, ccd or fabrik");
  r.solver = IkSolver::kAim;
  st = SolveIk(s, r, ws, result);
  EXPECT_EQ(st.message(), "free_root_rotation: the aim solver turns fixed joints; use dls, ccd or fabrik");
  // An effector on the root itself needs the root freed.
  r = ik_rigs::OneEffector(IkSolver::kDls, "Hips", std::nullopt, Eigen::Quaterniond::Identity());
  st = SolveIk(s, r, ws, result);
  EXPECT_EQ(st.message(),
            "effectors[0].joint: no free joint moves 'Hips' (check root, max_chain_depth, free_joints, free_root)");
  r.free_root_rotation = true;
  EXPECT_TRUE(SolveIk(s, r, ws, result).ok());
  EXPECT_TRUE(result.converged);
}

}  // namespace
}  // namespace armature
