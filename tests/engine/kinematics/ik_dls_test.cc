#include <chrono>
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "armature/engine/kinematics/ik.h"
#include "../testing/ik_rigs.h"

namespace armature {
namespace {

using ik_rigs::LimbCase;
using ik_rigs::WorldOf;

// Random reachable targets (forward kinematics of random poses within the
// limits) from the rest pose: success = within 1e-3 × chain length (and
// 1e-3 rad), judged by the engine's forward kinematics, not the solver's
// own residuals. Fixed seeds: the counts are deterministic.
TEST(IkDls, SuccessRateOnRandomReachableTargets) {
  IkWorkspace ws;
  IkResult result;
  for (const LimbCase& c : ik_rigs::StandardCases()) {
    std::mt19937_64 rng(1234);
    int reached = 0;
    for (int i = 0; i < 1000; ++i) {
      const ik_rigs::Target t = ik_rigs::TargetOf(c, ik_rigs::RandomPose(c, rng));
      ASSERT_TRUE(SolveIk(c.skeleton, ik_rigs::RequestFor(c, t), ws, result).ok());
      const ik_rigs::World w = WorldOf(c.skeleton, result.pose);
      const int e = c.skeleton.Find(c.effector);
      const double position_error = (w.transform[e] * c.offset - t.position).norm();
      const double rotation_error = w.rotation[e].angularDistance(t.rotation);
      const bool ok = ik_rigs::Reached(c, position_error, rotation_error);
      if (result.converged) EXPECT_TRUE(ok) << c.name << " target " << i;  // converged means reached
      EXPECT_TRUE(ik_rigs::WithinLimits(c.skeleton, c.limits, result.pose)) << c.name << " target " << i;
      reached += ok;
    }
    EXPECT_GE(reached, 995) << c.name;
  }
}

// Both hands at once, through the shared spine (root excluded: Hips).
TEST(IkDls, TwoHandsAtOnce) {
  const LimbCase body = ik_rigs::UpperBodyCase();
  const Skeleton& s = body.skeleton;
  std::mt19937_64 rng(3);
  IkWorkspace ws;
  IkResult result;
  int reached = 0;
  for (int i = 0; i < 100; ++i) {
    const std::vector<Trs> goal = ik_rigs::RandomPose(body, rng);
    const IkRequest r = ik_rigs::TwoHandsRequest(body, goal, 1e-3);
    ASSERT_TRUE(SolveIk(s, r, ws, result).ok());
    ASSERT_EQ(result.residuals.size(), 2u);
    const ik_rigs::World w = WorldOf(s, result.pose);
    const double left = (w.Position(s, "LeftHand") - *r.effectors[0].target_position).norm();
    const double right = (w.Position(s, "RightHand") - *r.effectors[1].target_position).norm();
    EXPECT_NEAR(left, result.residuals[0].position_error, 1e-9);
    EXPECT_NEAR(right, result.residuals[1].position_error, 1e-9);
    EXPECT_TRUE(ik_rigs::WithinLimits(s, body.limits, result.pose));
    // Only the spine and the arms moved; Neck and legs did not.
    for (const char* still : {"Hips", "Neck1", "LeftUpLeg", "LeftHand"})
      EXPECT_TRUE(result.pose[s.Find(still)].rotation.isApprox(s.rest[s.Find(still)].rotation)) << still;
    reached += result.converged && left <= 1e-3 && right <= 1e-3;
  }
  EXPECT_GE(reached, 98);
}

// A rotation target alone: the head turns to a given world orientation
// through neck and head, within their limits.
TEST(IkDls, OrientationTargetOnly) {
  const Skeleton s = ik_rigs::CmuLikeSkeleton();
  const Eigen::Quaterniond look = EulerToQuaternion(std::array{Axis::kZ, Axis::kY, Axis::kX},
                                                    std::array{0.2, 0.9, -0.3});  // within Neck1+Head ranges
  IkRequest r = ik_rigs::OneEffector(IkSolver::kDls, "Head", std::nullopt, look);
  r.limits = ik_rigs::CmuLimits();
  r.root = "Spine1";
  IkWorkspace ws;
  IkResult result;
  ASSERT_TRUE(SolveIk(s, r, ws, result).ok());
  EXPECT_TRUE(result.converged);
  EXPECT_LT(WorldOf(s, result.pose).rotation[s.Find("Head")].angularDistance(look), 1e-4);
  EXPECT_TRUE(ik_rigs::WithinLimits(s, r.limits, result.pose));
}

// Unreachable targets push joints against their limits: Euler boxes
// (shoulder), cones (hip) and hinges (elbow, knee) hold, and the best pose
// found is returned: nearer the target than the start.
TEST(IkDls, LimitsHoldAgainstUnreachableTargets) {
  IkWorkspace ws;
  IkResult result;
  for (const char* name : {"cmu_left_arm_reach", "cmu_right_leg_reach"}) {
    const LimbCase c = ik_rigs::StandardCase(name);
    const Eigen::Vector3d top = WorldOf(c.skeleton, c.skeleton.rest).Position(c.skeleton, c.joints[0]);
    const Eigen::Vector3d start = WorldOf(c.skeleton, c.skeleton.rest).Position(c.skeleton, c.effector);
    std::mt19937_64 rng(9);
    std::normal_distribution<double> n(0.0, 1.0);
    for (int i = 0; i < 100; ++i) {
      const Eigen::Vector3d target = top + 2.0 * c.chain_length * Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
      ASSERT_TRUE(SolveIk(c.skeleton, ik_rigs::RequestFor(c, {target, {}}), ws, result).ok());
      EXPECT_FALSE(result.converged);
      EXPECT_TRUE(result.stop == IkStop::kStalled || result.stop == IkStop::kIterationCap);
      EXPECT_TRUE(ik_rigs::WithinLimits(c.skeleton, c.limits, result.pose)) << c.name << " " << i;
      EXPECT_LT(result.residuals[0].position_error, (start - target).norm()) << c.name << " " << i;
    }
  }
}

TEST(IkDls, ConeLimitIsRespected) {
  // A single ball joint with a 30° cone about +Y swinging a 1-long bone.
  const Skeleton s = ik_rigs::BuildSkeleton({{"ball", nullptr, {0, 0, 0}}, {"tip", "ball", {0, 1, 0}}});
  IkRequest r = ik_rigs::OneEffector(IkSolver::kDls, "tip", Eigen::Vector3d(1, 0, 0));  // 90° away
  r.limits = {ik_rigs::SwingTwistLimit("ball", Eigen::Vector3d::UnitY(), 30, -10, 10)};
  r.free_root_rotation = true;  // the ball is the skeleton's root
  IkWorkspace ws;
  IkResult result;
  ASSERT_TRUE(SolveIk(s, r, ws, result).ok());
  EXPECT_FALSE(result.converged);
  const Eigen::Vector3d tip = WorldOf(s, result.pose).Position(s, "tip");
  const double swing = std::acos(tip.normalized().dot(Eigen::Vector3d::UnitY()));
  EXPECT_NEAR(swing, 30.0 * std::numbers::pi / 180.0, 1e-6);  // on the cone's edge, towards the target
  EXPECT_GT(tip.x(), 0.49);
  EXPECT_TRUE(ik_rigs::WithinLimits(s, r.limits, result.pose));
}

// Three equal hinges in a plane: a 1-D family of solutions for a 2-D target.
// With regularization the solver settles on the solution nearest the start
// pose, found here by brute force.
TEST(IkDls, RedundantChainPrefersTheStartPose) {
  const Skeleton s = ik_rigs::BuildSkeleton(
      {{"a", nullptr, {0, 0, 0}}, {"b", "a", {1, 0, 0}}, {"c", "b", {1, 0, 0}}, {"tip", "c", {1, 0, 0}}});
  std::vector<JointLimit> limits;
  for (const char* j : {"a", "b", "c"}) limits.push_back(ik_rigs::HingeLimit(j, Eigen::Vector3d::UnitZ(), -180, 180));
  auto angles_of = [&](const std::vector<Trs>& pose) {
    Eigen::Vector3d q;
    for (int j = 0; j < 3; ++j) q[j] = 2.0 * std::atan2(pose[j].rotation.z(), pose[j].rotation.w());
    return q;
  };
  auto wrap = [](Eigen::Vector3d v) {
    for (double& x : v) x = std::remainder(x, 2.0 * std::numbers::pi);
    return v;
  };
  // Nearest solution to q0 reaching (x, y): sweep q1, solve the last two links.
  auto nearest = [&](const Eigen::Vector3d& q0, const Eigen::Vector2d& target) {
    double best = INFINITY;
    for (int k = 0; k < 50000; ++k) {
      const double q1 = -std::numbers::pi + 2.0 * std::numbers::pi * k / 50000;
      const Eigen::Vector2d rest = target - Eigen::Vector2d(std::cos(q1), std::sin(q1));
      const double c3 = (rest.squaredNorm() - 2.0) / 2.0;
      if (std::abs(c3) > 1) continue;
      for (double sign : {1.0, -1.0}) {
        const double q3 = sign * std::acos(c3);
        const double q2 = std::atan2(rest.y(), rest.x()) - std::atan2(std::sin(q3), 1 + std::cos(q3)) - q1;
        best = std::min(best, wrap(Eigen::Vector3d(q1, q2, q3) - q0).norm());
      }
    }
    return best;
  };
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  IkWorkspace ws;
  IkResult result;
  double plain_total = 0;
  int nearest_found = 0;
  for (int i = 0; i < 20; ++i) {
    std::vector<Trs> start = s.rest;
    for (int j = 0; j < 3; ++j) start[j].rotation = AxisRotation(Axis::kZ, u(rng));
    const Eigen::Vector3d q0 = angles_of(start);
    const Eigen::Vector2d target(1.2 + 0.5 * u(rng), 0.8 * u(rng));
    const double best = nearest(q0, target);
    double excess[2];
    for (int k = 0; k < 2; ++k) {
      IkRequest r = ik_rigs::OneEffector(IkSolver::kDls, "tip", Eigen::Vector3d(target.x(), target.y(), 0));
      r.start_pose = start;
      r.limits = limits;
      r.free_root_rotation = true;   // the first hinge is the skeleton's root
      r.options.regularization = k;  // off, then all the way
      r.options.position_tolerance = 1e-4;
      ASSERT_TRUE(SolveIk(s, r, ws, result).ok());
      ASSERT_TRUE(result.converged) << i << " regularization " << k;
      excess[k] = wrap(angles_of(result.pose) - q0).norm() - best;
      EXPECT_GE(excess[k], -1e-3);  // nothing beats the nearest solution
    }
    EXPECT_LE(excess[1], excess[0] + 1e-6) << i;  // never further from the start
    nearest_found += excess[1] < 1e-3;
    plain_total += excess[0];
  }
  EXPECT_GE(nearest_found, 15);       // the rest: a nearer-by local minimum of the distance
  EXPECT_GT(plain_total / 20, 0.05);  // plain DLS lands near, not on, the nearest solution
}

TEST(IkDls, FreeRootTranslationExtendsReach) {
  const Skeleton s = ik_rigs::CmuLikeSkeleton();
  const Eigen::Vector3d far = WorldOf(s, s.rest).Position(s, "LeftHand") + Eigen::Vector3d(30, 0, 0);
  IkRequest r = ik_rigs::OneEffector(IkSolver::kDls, "LeftHand", far);
  r.root = "LeftShoulder";
  IkWorkspace ws;
  IkResult result;
  ASSERT_TRUE(SolveIk(s, r, ws, result).ok());
  EXPECT_FALSE(result.converged);
  r.free_root_translation = true;
  ASSERT_TRUE(SolveIk(s, r, ws, result).ok());
  EXPECT_TRUE(result.converged);
  EXPECT_GT(result.pose[0].translation.x(), 20.0);  // the hips walked over
  EXPECT_LT((WorldOf(s, result.pose).Position(s, "LeftHand") - far).norm(), 1e-3);
}

TEST(IkDls, WeightsTradeOffConflictingEffectors) {
  // One joint, two effectors on the same tip wanting opposite sides.
  const Skeleton s = ik_rigs::BuildSkeleton({{"a", nullptr, {0, 0, 0}}, {"tip", "a", {1, 0, 0}}});
  auto solve = [&](double w0, double w1) {
    IkRequest r;
    for (double y : {1.0, -1.0}) {
      IkEffector e;
      e.joint = "tip";
      e.target_position = Eigen::Vector3d(0, y, 0);
      r.effectors.push_back(e);
    }
    r.free_root_rotation = true;  // the one joint is the skeleton's root
    r.effectors[0].position_weight = w0;
    r.effectors[1].position_weight = w1;
    IkWorkspace ws;
    IkResult result;
    EXPECT_TRUE(SolveIk(s, r, ws, result).ok());
    return WorldOf(s, result.pose).Position(s, "tip");
  };
  EXPECT_GT(solve(4.0, 1.0).y(), 0.5);
  EXPECT_LT(solve(1.0, 4.0).y(), -0.5);
}

TEST(IkDls, DeadlineAndCancelStopTheSolve) {
  const LimbCase c = ik_rigs::StandardCase("seven_dof_pose");
  std::mt19937_64 rng(1);
  IkRequest r = ik_rigs::RequestFor(c, ik_rigs::TargetOf(c, ik_rigs::RandomPose(c, rng)));
  IkWorkspace ws;
  IkResult result;

  r.deadline = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  ASSERT_TRUE(SolveIk(c.skeleton, r, ws, result).ok());
  EXPECT_EQ(result.stop, IkStop::kDeadline);
  EXPECT_EQ(result.iterations, 0);
  EXPECT_FALSE(result.converged);
  EXPECT_EQ(result.pose.size(), c.skeleton.size());
  EXPECT_EQ(IkStopStatus(result).code(), StatusCode::kDeadlineExceeded);

  r.deadline.reset();
  int calls = 0;
  r.should_stop = [&] { return ++calls > 3; };
  ASSERT_TRUE(SolveIk(c.skeleton, r, ws, result).ok());
  EXPECT_EQ(result.stop, IkStop::kCancelled);
  EXPECT_EQ(result.iterations, 3);  // checked once before each iteration
  EXPECT_EQ(IkStopStatus(result).code(), StatusCode::kCancelled);

  r.should_stop = nullptr;
  r.options.max_iterations = 2;
  ASSERT_TRUE(SolveIk(c.skeleton, r, ws, result).ok());
  EXPECT_EQ(result.iterations, 2);
  EXPECT_EQ(result.stop, IkStop::kIterationCap);
  EXPECT_TRUE(IkStopStatus(result).ok());

  r.options.max_iterations = 200;
  ASSERT_TRUE(SolveIk(c.skeleton, r, ws, result).ok());
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(result.stop, IkStop::kConverged);
}

TEST(IkDls, StartPoseAlreadySolvedTakesNoIteration) {
  const LimbCase c = ik_rigs::StandardCase("cmu_left_arm_reach");
  std::mt19937_64 rng(4);
  const std::vector<Trs> pose = ik_rigs::RandomPose(c, rng);
  IkRequest r = ik_rigs::RequestFor(c, ik_rigs::TargetOf(c, pose));
  r.start_pose = pose;
  IkWorkspace ws;
  IkResult result;
  ASSERT_TRUE(SolveIk(c.skeleton, r, ws, result).ok());
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(result.iterations, 0);
  for (size_t j = 0; j < pose.size(); ++j) EXPECT_TRUE(result.pose[j].rotation.isApprox(pose[j].rotation, 1e-12));
}

}  // namespace
}  // namespace armature
