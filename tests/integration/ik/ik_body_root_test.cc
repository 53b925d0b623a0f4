// The body root on a Mixamo-style rig: RobotExpressive under `Armature`, a
// still node at scale 0.01, with its joints in centimetres (made by
// web/test/support/mixamo_rig.mjs with node). A left-hand reach keeps the joint that
// carries the body (`Body`: every clip but Dance translates it, and both legs
// hang from it) where it stands, so the hips and both feet do not move; the
// answer names it. Before, the kept root was the topmost node, and the reach
// turned `Bone` and `Body` above the arm, moving the feet. Over gRPC on a real
// armature-server; skipped when ../shared/data or node is absent.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "armature/client.h"
#include "ik/ik_rig.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

constexpr double kTime = 1.0;
// RobotExpressive's hips are `Body`; its `Hips` is the spine's base below it, which the reach may turn.
const char* const kStill[] = {"Body", "UpperLegL", "LowerLegL", "FootL", "UpperLegR", "LowerLegR", "FootR"};

class IkBodyRoot : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string robot = SharedData("gltf/RobotExpressive/RobotExpressive.glb");
    if (robot.empty()) GTEST_SKIP() << "../shared/data (RobotExpressive.glb) is absent";
    if (std::system("node --version >/dev/null 2>&1") != 0) GTEST_SKIP() << "node is not installed";
    const std::string glb = (files_.path() / "mixamo.glb").string();
    const CommandResult made =
        RunCommand("node " + ShellQuote(std::string(ARMATURE_TEST_DIR) + "/../web/test/support/mixamo_rig.mjs") + " " +
                   ShellQuote(robot) + " " + ShellQuote(glb));
    ASSERT_EQ(made.exit_code, 0) << made.err;
    server_ = std::make_unique<ServerProcess>(data_.path());
    client_ = std::make_unique<client::Client>(OptionsFor(*server_));
    client_->ImportFile(glb, "mixamo");
    skeleton_ = client_->GetSkeleton("mixamo");
    v1::EvaluateClipRequest idle;
    idle.set_clip("mixamo.Idle");
    idle.add_times(kTime);
    idle.set_space(v1::WORLD);
    clip_world_ = client_->EvaluateClip(idle).poses(0);
  }
  int Joint(const std::string& name) const { return JointIndex(skeleton_, name); }
  Eigen::Quaterniond Rotation(const v1::Pose& pose, int j) const {
    return {pose.rotations(4 * j), pose.rotations(4 * j + 1), pose.rotations(4 * j + 2), pose.rotations(4 * j + 3)};
  }

  TempDir data_, files_;
  std::unique_ptr<ServerProcess> server_;
  std::unique_ptr<client::Client> client_;
  v1::Skeleton skeleton_;
  v1::Pose clip_world_;
};

TEST_F(IkBodyRoot, AHandReachOnAMixamoStyleRigLeavesTheHipsAndFeetStill) {
  const int armature = Joint("Armature");
  EXPECT_NEAR(skeleton_.joints(armature).rest_scale(0), 0.01, 1e-9);
  const int hand = Joint("Palm2L");
  // A reach 15 % of the figure's hip height up, forward and out from where the clip has the hand.
  const double height = At3(clip_world_.translations(), Joint("Body")).y();
  const Eigen::Vector3d target = At3(clip_world_.translations(), hand) + 0.15 * height * Eigen::Vector3d(1, 1, 1);
  v1::SolveIkRequest r;
  r.set_skeleton("mixamo");
  r.mutable_from_clip()->set_clip("mixamo.Idle");
  r.mutable_from_clip()->set_time(kTime);
  *r.add_effectors() = Effector("Palm2L", target);
  const v1::SolveIkResponse response = client_->SolveIk(r);
  ASSERT_EQ(response.residuals_size(), 1);
  EXPECT_EQ(response.residuals(0).body_root(), "Body");
  const double reached = response.residuals(0).position_error();
  EXPECT_TRUE(response.converged()) << "off by " << reached;

  double moved = 0, turned = 0;
  for (const char* name : kStill) {
    const int j = Joint(name);
    moved = std::max(moved, (At3(response.world().translations(), j) - At3(clip_world_.translations(), j)).norm());
    turned = std::max(turned, Rotation(response.world(), j).angularDistance(Rotation(clip_world_, j)));
  }
  const double hand_moved = (At3(response.world().translations(), hand) - At3(clip_world_.translations(), hand)).norm();
  std::printf("  hand moved %.3f (hip height %.3f); body, hips, legs and feet moved %.3g and turned %.3g°\n",
              hand_moved, height, moved, turned * 180 / std::numbers::pi);
  EXPECT_GT(hand_moved, 0.1 * height);
  EXPECT_LT(moved, 1e-6 * height);
  EXPECT_LT(turned, 1e-6);

  // ROOT_ROTATION turns the body root, not the still Armature above it.
  r.set_free_root(v1::ROOT_ROTATION);
  const v1::SolveIkResponse free = client_->SolveIk(r);
  EXPECT_EQ(free.residuals(0).body_root(), "Body");
  for (int k = 0; k < 4; ++k)
    EXPECT_EQ(free.local().rotations(4 * armature + k), response.local().rotations(4 * armature + k));

  // Out of the arm's reach: ROOT_TRANSLATION moves the body root in world space (through the
  // scaled, turned Armature above it) until the hand is there.
  const Eigen::Vector3d far = At3(clip_world_.translations(), hand) + Eigen::Vector3d(0, 0, 3 * height);
  r.mutable_effectors(0)->clear_target_position();
  for (int k = 0; k < 3; ++k) r.mutable_effectors(0)->add_target_position(far[k]);
  r.set_free_root(v1::ROOT_FIXED);
  EXPECT_FALSE(client_->SolveIk(r).converged());
  r.set_free_root(v1::ROOT_TRANSLATION);
  const v1::SolveIkResponse carried = client_->SolveIk(r);
  EXPECT_TRUE(carried.converged()) << "off by " << carried.residuals(0).position_error();
  const int body = Joint("Body");
  EXPECT_GT((At3(carried.world().translations(), body) - At3(clip_world_.translations(), body)).norm(), height);
}

}  // namespace
}  // namespace armature::testing
