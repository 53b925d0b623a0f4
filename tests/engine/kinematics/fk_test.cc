#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "armature/engine/kinematics/fk.h"
#include "armature/engine/math/rotation.h"

namespace armature {
namespace {

// The planar two-link arm of the lectures: x = l1 cos θ1 + l2 cos(θ1+θ2),
// y = l1 sin θ1 + l2 sin(θ1+θ2), with joints rotating about Z.
TEST(Fk, PlanarTwoLinkArmMatchesTextbookFormula) {
  const double l1 = 2.0, l2 = 1.5;
  Skeleton s;
  s.names = {"shoulder", "elbow", "hand"};
  s.parents = {-1, 0, 1};
  s.rest.resize(3);
  s.rest[1].translation = {l1, 0, 0};
  s.rest[2].translation = {l2, 0, 0};
  s.channels.resize(3);
  s.end_sites.resize(3);
  ASSERT_TRUE(s.Validate().ok());

  for (double t1 : {0.0, 0.3, 1.2, -2.0}) {
    for (double t2 : {0.0, 0.7, -1.1, 3.0}) {
      std::vector<Trs> local = s.rest;
      local[0].rotation = AxisRotation(Axis::kZ, t1);
      local[1].rotation = AxisRotation(Axis::kZ, t2);
      std::vector<Eigen::Affine3d> world(3);
      ComputeWorld(s, local, world);
      const Eigen::Vector3d hand = world[2].translation();
      EXPECT_NEAR(hand.x(), l1 * std::cos(t1) + l2 * std::cos(t1 + t2), 1e-12);
      EXPECT_NEAR(hand.y(), l1 * std::sin(t1) + l2 * std::sin(t1 + t2), 1e-12);
      EXPECT_NEAR(hand.z(), 0.0, 1e-12);
    }
  }
}

// A floating root: the root's own translation and rotation place the chain.
TEST(Fk, FloatingRootMovesWholeChain) {
  Skeleton s;
  s.names = {"root", "child"};
  s.parents = {-1, 0};
  s.rest.resize(2);
  s.rest[1].translation = {0, 1, 0};
  s.channels.resize(2);
  s.end_sites.resize(2);
  std::vector<Trs> local = s.rest;
  local[0].translation = {5, 0, 0};
  local[0].rotation = AxisRotation(Axis::kX, std::numbers::pi / 2);  // y → z
  std::vector<Eigen::Affine3d> world(2);
  ComputeWorld(s, local, world);
  EXPECT_TRUE(world[1].translation().isApprox(Eigen::Vector3d(5, 0, 1), 1e-12));
}

TEST(Fk, PoseFromArraysRejectsBadInput) {
  Skeleton s;
  s.names = {"a"};
  s.parents = {-1};
  s.rest.resize(1);
  s.channels.resize(1);
  s.end_sites.resize(1);
  std::vector<Trs> out(1);
  const float zero[4] = {0, 0, 0, 0};
  EXPECT_EQ(PoseFromArrays(s, zero, {}, out).code(), StatusCode::kInvalidArgument);
  const float nan_t[3] = {0, NAN, 0};
  const float id[4] = {1, 0, 0, 0};
  Status st = PoseFromArrays(s, id, nan_t, out);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("translations"), std::string::npos);
  const float q2[4] = {2, 0, 0, 0};
  EXPECT_TRUE(PoseFromArrays(s, q2, {}, out).ok());
  EXPECT_NEAR(out[0].rotation.w(), 1.0, 1e-12);
}

}  // namespace
}  // namespace armature
