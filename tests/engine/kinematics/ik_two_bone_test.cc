#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "armature/engine/kinematics/ik.h"
#include "armature/engine/kinematics/ik_two_bone.h"
#include "../testing/ik_rigs.h"

namespace armature {
namespace {

using ik_rigs::WorldOf;

// shoulder → elbow → hand along +X, bones l1 and l2.
Skeleton PlanarArm(double l1, double l2) {
  return ik_rigs::BuildSkeleton(
      {{"shoulder", nullptr, {0, 0, 0}}, {"elbow", "shoulder", {l1, 0, 0}}, {"hand", "elbow", {l2, 0, 0}}});
}

IkRequest TwoBoneRequest(const std::string& joint, const Eigen::Vector3d& target) {
  return ik_rigs::OneEffector(IkSolver::kTwoBone, joint, target);
}

// The angle of a rotation about +Z, checking it is one.
double ZAngle(const Eigen::Quaterniond& q) {
  EXPECT_NEAR(q.x(), 0.0, 1e-9);
  EXPECT_NEAR(q.y(), 0.0, 1e-9);
  return 2.0 * std::atan2(q.z(), q.w());
}

double Wrap(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

// The lectures' planar two-link arm: θ2 = ±acos((x²+y²−l1²−l2²)/(2 l1 l2)),
// θ1 = atan2(y, x) − atan2(l2 sin θ2, l1 + l2 cos θ2), and the hand lands at
// x = l1 cos θ1 + l2 cos(θ1+θ2), y = l1 sin θ1 + l2 sin(θ1+θ2). The pole picks
// the elbow's side.
TEST(IkTwoBone, MatchesTextbookPlanarTwoLinkFormula) {
  const double l1 = 2.0, l2 = 1.5;
  const Skeleton s = PlanarArm(l1, l2);
  IkWorkspace ws;
  IkResult result;
  int cases = 0;
  for (double x : {2.5, 0.8, -1.7, 0.6}) {
    for (double y : {0.4, 2.2, -1.1}) {
      const double c2 = (x * x + y * y - l1 * l1 - l2 * l2) / (2 * l1 * l2);
      ASSERT_LT(std::abs(c2), 1.0);
      for (double side : {1.0, -1.0}) {
        const double t2 = side * std::acos(c2);
        const double t1 = std::atan2(y, x) - std::atan2(l2 * std::sin(t2), l1 + l2 * std::cos(t2));
        const Eigen::Vector3d elbow(l1 * std::cos(t1), l1 * std::sin(t1), 0);
        IkRequest r = TwoBoneRequest("hand", {x, y, 0});
        r.effectors[0].pole = elbow * 3.0;  // far out on the elbow's side
        ASSERT_TRUE(SolveIk(s, r, ws, result).ok());
        EXPECT_TRUE(result.converged);
        EXPECT_NEAR(Wrap(ZAngle(result.pose[0].rotation) - t1), 0.0, 1e-9) << x << "," << y << " side " << side;
        EXPECT_NEAR(Wrap(ZAngle(result.pose[1].rotation) - t2), 0.0, 1e-9);
        const ik_rigs::World w = WorldOf(s, result.pose);
        EXPECT_NEAR(w.Position(s, "hand").x(), l1 * std::cos(t1) + l2 * std::cos(t1 + t2), 1e-9);
        EXPECT_NEAR(w.Position(s, "hand").y(), l1 * std::sin(t1) + l2 * std::sin(t1 + t2), 1e-9);
        EXPECT_LT((w.Position(s, "elbow") - elbow).norm(), 1e-9);
        ++cases;
      }
    }
  }
  EXPECT_EQ(cases, 24);
}

// On a 3-D leg the knee ends up in the half-plane through hip and target
// that contains the pole, whatever the pole's direction.
TEST(IkTwoBone, KneeFollowsPole) {
  const Skeleton s = ik_rigs::CmuLikeSkeleton();
  const ik_rigs::World rest = WorldOf(s, s.rest);
  const Eigen::Vector3d hip = rest.Position(s, "RightUpLeg");
  const Eigen::Vector3d target = hip + Eigen::Vector3d(-1.0, -11.0, 3.0);
  IkWorkspace ws;
  IkResult result;
  for (const Eigen::Vector3d& pole_direction :
       {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(1, 0.2, -1)}) {
    IkRequest r = TwoBoneRequest("RightFoot", target);
    r.effectors[0].pole = hip + 20.0 * pole_direction;
    ASSERT_TRUE(SolveIk(s, r, ws, result).ok());
    EXPECT_TRUE(result.converged);
    const ik_rigs::World w = WorldOf(s, result.pose);
    EXPECT_LT((w.Position(s, "RightFoot") - target).norm(), 1e-9);
    const Eigen::Vector3d line = (target - hip).normalized();
    auto across = [&](const Eigen::Vector3d& p) {
      const Eigen::Vector3d v = p - hip;
      return Eigen::Vector3d(v - v.dot(line) * line);
    };
    const Eigen::Vector3d knee = across(w.Position(s, "RightLeg")).normalized();
    const Eigen::Vector3d pole = across(*r.effectors[0].pole).normalized();
    EXPECT_GT(knee.dot(pole), 1.0 - 1e-9) << pole_direction.transpose();
    // Bone lengths are kept.
    EXPECT_NEAR((w.Position(s, "RightLeg") - hip).norm(), s.rest[s.Find("RightLeg")].translation.norm(), 1e-9);
  }
}

TEST(IkTwoBone, SoftenedReachIsContinuousAndNeverFullyExtends) {
  const double max_reach = 2.0, softness = 0.1;
  EXPECT_DOUBLE_EQ(SoftenedReach(1.5, max_reach, softness), 1.5);  // below the soft zone: exact
  EXPECT_DOUBLE_EQ(SoftenedReach(1.8, max_reach, softness), 1.8);  // its start
  EXPECT_DOUBLE_EQ(SoftenedReach(2.5, max_reach, 0.0), 2.5);       // off
  double previous = SoftenedReach(1.7, max_reach, softness);
  for (double d = 1.701; d < 4.0; d += 0.001) {
    const double r = SoftenedReach(d, max_reach, softness);
    EXPECT_GT(r, previous);                  // still follows the target
    EXPECT_LE(r - previous, 0.001 + 1e-12);  // slope ≤ 1: no jump
    EXPECT_LT(r, max_reach);
    previous = r;
  }
  EXPECT_GT(previous, max_reach - 1e-3);  // approaches full reach
}

// Sweeping the target through full extension: without softening the elbow
// snaps straight over the last millimetre; with it the elbow angle changes
// gently and the arm never quite straightens.
TEST(IkTwoBone, SofteningAvoidsSnapNearFullExtension) {
  const Skeleton s = PlanarArm(1.0, 1.0);
  IkWorkspace ws;
  IkResult result;
  auto largest_elbow_step = [&](double softness, double* min_elbow) {
    double largest = 0, previous = NAN;
    *min_elbow = INFINITY;
    for (double d = 1.6; d <= 2.4; d += 0.001) {
      IkRequest r = TwoBoneRequest("hand", {d * std::cos(0.3), d * std::sin(0.3), 0});
      r.effectors[0].pole = Eigen::Vector3d(0, 5, 0);
      r.options.softness = softness;
      EXPECT_TRUE(SolveIk(s, r, ws, result).ok());
      const double elbow = std::abs(ZAngle(result.pose[1].rotation));
      if (!std::isnan(previous)) largest = std::max(largest, std::abs(elbow - previous));
      *min_elbow = std::min(*min_elbow, elbow);
      previous = elbow;
    }
    return largest;
  };
  double min_hard, min_soft;
  const double hard = largest_elbow_step(0.0, &min_hard);
  const double soft = largest_elbow_step(0.1, &min_soft);
  EXPECT_GT(hard, 0.04);       // acos near 1: ~0.045 rad over the last 0.001
  EXPECT_LT(soft, 0.004);      // bounded slope through the soft zone
  EXPECT_LT(min_hard, 1e-9);   // straight once out of reach
  EXPECT_GT(min_soft, 0.005);  // never quite straight
}

TEST(IkTwoBone, UnreachableTargetIsBestEffort) {
  const Skeleton s = PlanarArm(2.0, 1.5);
  IkWorkspace ws;
  IkResult result;
  const Eigen::Vector3d target(3.0, 4.0, 0.0);  // 5 away, reach 3.5
  ASSERT_TRUE(SolveIk(s, TwoBoneRequest("hand", target), ws, result).ok());
  EXPECT_FALSE(result.converged);
  EXPECT_EQ(result.stop, IkStop::kDone);
  const Eigen::Vector3d hand = WorldOf(s, result.pose).Position(s, "hand");
  EXPECT_LT((hand - 3.5 * target.normalized()).norm(), 1e-9);  // straight, pointing at it
  EXPECT_NEAR(result.residuals[0].position_error, 1.5, 1e-9);
  EXPECT_FALSE(result.residuals[0].reached);
}

// A rotation target turns the end joint; the triangle is solved for the
// joint's origin so an offset effector point still lands on the target.
TEST(IkTwoBone, RotationTargetOnTheEndJoint) {
  const Skeleton s = ik_rigs::CmuLikeSkeleton();
  const ik_rigs::World rest = WorldOf(s, s.rest);
  const Eigen::Vector3d target = rest.Position(s, "LeftArm") + Eigen::Vector3d(4.0, -3.0, 3.0);
  const Eigen::Quaterniond rotation(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  IkRequest r = TwoBoneRequest("LeftHand", target);
  r.effectors[0].target_rotation = rotation;
  r.effectors[0].local_offset = Eigen::Vector3d(1.2, 0, 0);  // the fingers
  IkWorkspace ws;
  IkResult result;
  ASSERT_TRUE(SolveIk(s, r, ws, result).ok());
  EXPECT_TRUE(result.converged);
  const ik_rigs::World w = WorldOf(s, result.pose);
  const int hand = s.Find("LeftHand");
  EXPECT_LT((w.transform[hand] * Eigen::Vector3d(1.2, 0, 0) - target).norm(), 1e-9);
  EXPECT_LT(w.rotation[hand].angularDistance(rotation), 1e-9);
}

TEST(IkTwoBone, SolvesBothLegsInOneRequest) {
  const Skeleton s = ik_rigs::CmuLikeSkeleton();
  const ik_rigs::World rest = WorldOf(s, s.rest);
  IkRequest r = TwoBoneRequest("LeftFoot", rest.Position(s, "LeftFoot") + Eigen::Vector3d(0, 3, 2));
  r.effectors.push_back(r.effectors[0]);
  r.effectors[1].joint = "RightFoot";
  r.effectors[1].target_position = rest.Position(s, "RightFoot") + Eigen::Vector3d(0, 1, -2);
  IkWorkspace ws;
  IkResult result;
  ASSERT_TRUE(SolveIk(s, r, ws, result).ok());
  EXPECT_TRUE(result.converged);
  const ik_rigs::World w = WorldOf(s, result.pose);
  EXPECT_LT((w.Position(s, "LeftFoot") - *r.effectors[0].target_position).norm(), 1e-9);
  EXPECT_LT((w.Position(s, "RightFoot") - *r.effectors[1].target_position).norm(), 1e-9);
}

}  // namespace
}  // namespace armature
