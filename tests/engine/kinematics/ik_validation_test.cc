// Bad input gets INVALID_ARGUMENT naming the field, never a crash.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "armature/engine/kinematics/ik.h"
#include "../testing/ik_rigs.h"

namespace armature {
namespace {

class IkValidationTest : public testing::Test {
 protected:
  IkValidationTest() : skeleton_(ik_rigs::CmuLikeSkeleton()) {
    IkEffector left;
    left.joint = "LeftHand";
    left.target_position = Eigen::Vector3d(10, 15, 5);
    IkEffector right = left;
    right.joint = "RightHand";
    right.target_position = Eigen::Vector3d(-10, 15, 5);
    request_.effectors = {left, right};
    request_.limits = ik_rigs::CmuLimits();
    request_.root = "Hips";
  }

  // The message of the error, or "" (and a failure) when the solve passed.
  std::string ErrorOf(const IkRequest& r) {
    const Status st = SolveIk(skeleton_, r, ws_, result_);
    EXPECT_FALSE(st.ok());
    if (st.ok()) return "";
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << st.message();
    return st.message();
  }

  Skeleton skeleton_;
  IkRequest request_;
  IkWorkspace ws_;
  IkResult result_;
  std::string skeleton_names_front_;
};

TEST_F(IkValidationTest, ValidRequestSolves) {
  ASSERT_TRUE(SolveIk(skeleton_, request_, ws_, result_).ok());
  EXPECT_EQ(result_.residuals.size(), 2u);
}

TEST_F(IkValidationTest, UnknownJoints) {
  // Each message names the field and the joint, suggests a near miss and lists the skeleton's joints.
  auto starts = [this](const std::string& message, const std::string& prefix) {
    EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
    EXPECT_NE(message.find("joints: " + std::string(skeleton_names_front_)), std::string::npos) << message;
  };
  skeleton_names_front_ = skeleton_.names.front();
  IkRequest r = request_;
  r.effectors[1].joint = "LeftHandd";
  starts(ErrorOf(r), "effectors[1].joint: unknown joint 'LeftHandd'; did you mean 'LeftHand'? (the skeleton's ");
  r = request_;
  r.limits[4].joint = "Elbow";
  starts(ErrorOf(r), "limits[4].joint: unknown joint 'Elbow'");
  r = request_;
  r.root = "Pelvis";
  starts(ErrorOf(r), "root: unknown joint 'Pelvis'");
  r = request_;
  r.root.clear();
  r.free_joints = {"LeftArm", "Shoulder"};
  starts(ErrorOf(r), "free_joints[1]: unknown joint 'Shoulder'");
}

TEST_F(IkValidationTest, NonFiniteNumbers) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  IkRequest r = request_;
  r.effectors[0].target_position->y() = nan;
  EXPECT_EQ(ErrorOf(r), "effectors[0].target_position: not finite");
  r = request_;
  r.effectors[1].target_rotation = Eigen::Quaterniond(0, 0, 0, 0);
  EXPECT_EQ(ErrorOf(r), "effectors[1].target_rotation: not finite or a zero quaternion");
  r = request_;
  r.effectors[0].local_offset.x() = INFINITY;
  EXPECT_EQ(ErrorOf(r), "effectors[0].local_offset: not finite");
  r = request_;
  r.effectors[0].position_weight = -1;
  EXPECT_EQ(ErrorOf(r), "effectors[0].position_weight: negative or not finite");
  r = request_;
  r.limits[0].max_deg[2] = nan;
  EXPECT_EQ(ErrorOf(r), "limits[0].max_deg[2]: not finite");
  std::vector<Trs> pose = skeleton_.rest;
  pose[3].translation.z() = nan;
  r = request_;
  r.start_pose = pose;
  EXPECT_EQ(ErrorOf(r), "start_pose[3] ('LeftLeg'): not finite or a zero quaternion");
  pose.pop_back();
  r.start_pose = pose;
  EXPECT_EQ(ErrorOf(r), "start_pose: expected 31 joints, got 30");
}

TEST_F(IkValidationTest, ContradictoryLimits) {
  IkRequest r = request_;
  r.limits[2].min_deg[0] = 50;  // LeftHand Z: [50, 70] ok
  ASSERT_TRUE(SolveIk(skeleton_, r, ws_, result_).ok());
  r.limits[2].min_deg[0] = 90;  // > 70
  EXPECT_EQ(ErrorOf(r), "limits[2].min_deg[0] > max_deg[0] (90 > 70)");
  r = request_;
  r.limits[6].cone_deg = -5;
  EXPECT_EQ(ErrorOf(r), "limits[6].cone_deg: negative (-5)");
  r = request_;
  r.limits[6].cone_deg = 200;
  EXPECT_EQ(ErrorOf(r), "limits[6].cone_deg: above 180 (200)");
  r = request_;
  r.limits[7].twist_min_deg = 10;  // knee hinge [10, 150] ok, then [160, 150]
  ASSERT_TRUE(SolveIk(skeleton_, r, ws_, result_).ok());
  r.limits[7].twist_min_deg = 160;
  EXPECT_EQ(ErrorOf(r), "limits[7].twist_min_deg > twist_max_deg (160 > 150)");
  r = request_;
  r.limits[7].axis = Eigen::Vector3d::Zero();
  EXPECT_EQ(ErrorOf(r), "limits[7].axis: zero length or not finite");
  r = request_;
  r.limits[0].order = {Axis::kZ, Axis::kZ, Axis::kX};
  EXPECT_EQ(ErrorOf(r), "limits[0].order: neighbouring axes must differ");
  r = request_;
  r.limits[0].min_deg[1] = -400;
  EXPECT_EQ(ErrorOf(r), "limits[0].min_deg[1]: below -360 (-400)");
  r = request_;
  r.limits.push_back(ik_rigs::HingeLimit("LeftForeArm", Eigen::Vector3d::UnitY(), 0, 90));
  EXPECT_EQ(ErrorOf(r), "limits[17].joint: 'LeftForeArm' is already limited by limits[1]");
}

TEST_F(IkValidationTest, ZeroLengthAndEmptyChains) {
  IkRequest r = request_;
  r.effectors.resize(1);
  r.root = "LeftHand";
  r.effectors[0].joint = "LeftHand";
  EXPECT_EQ(ErrorOf(r),
            "effectors[0].joint: no free joint moves 'LeftHand' (check root, max_chain_depth, free_joints, free_root)");
  r.root.clear();
  r.effectors[0].joint = "LHipJoint";  // hangs from the root, which stays by default
  EXPECT_EQ(
      ErrorOf(r),
      "effectors[0].joint: no free joint moves 'LHipJoint' (check root, max_chain_depth, free_joints, free_root)");
  r.free_root_rotation = true;  // at the hips' origin: turning them cannot move it
  EXPECT_EQ(
      ErrorOf(r),
      "effectors[0].joint: zero-length chain: the free joints above 'LHipJoint' coincide with the effector point");
  r.free_root_rotation = false;
  r.effectors[0].joint = "LeftUpLeg";
  r.solver = IkSolver::kTwoBone;  // LHipJoint sits on Hips
  r.limits.clear();
  EXPECT_EQ(ErrorOf(r), "effectors[0].joint: zero-length two-bone chain: bone 'Hips' has no length");
  r.effectors[0].joint = "LHipJoint";
  EXPECT_EQ(ErrorOf(r), "effectors[0].joint: two-bone needs a parent and a grandparent of 'LHipJoint'");
  r = request_;
  r.effectors.clear();
  EXPECT_EQ(ErrorOf(r), "effectors: empty");
  r = request_;
  r.root = "LeftArm";
  EXPECT_EQ(ErrorOf(r), "root: 'LeftArm' is not an ancestor of effectors[1].joint 'RightHand'");
}

TEST_F(IkValidationTest, SolverSpecificRules) {
  IkRequest r = request_;
  r.solver = IkSolver::kCcd;
  EXPECT_EQ(ErrorOf(r), "effectors: the ccd solver takes one effector, got 2");
  r.effectors.resize(1);
  r.effectors[0].target_position.reset();
  r.effectors[0].target_rotation = Eigen::Quaterniond::Identity();
  EXPECT_EQ(ErrorOf(r), "effectors[0].target_position: required by the ccd solver");
  r = request_;
  r.solver = IkSolver::kTwoBone;
  EXPECT_EQ(ErrorOf(r),
            "limits[0].joint: the two-bone solver does not apply limits ('LeftArm' is in effectors[0]'s chain); "
            "use dls, ccd or fabrik");
  r = request_;
  r.solver = IkSolver::kAim;
  r.effectors[0].aim_axis = Eigen::Vector3d::Zero();
  EXPECT_EQ(ErrorOf(r), "effectors[0].aim_axis: zero length or not finite");
  r.effectors[0].aim_axis = Eigen::Vector3d::UnitZ();
  r.effectors[0].up_hint = Eigen::Vector3d::UnitY();
  r.effectors[0].up_axis = Eigen::Vector3d(0, 0, 2);
  EXPECT_EQ(ErrorOf(r), "effectors[0].up_axis: parallel to aim_axis");
  r = request_;
  r.solver = IkSolver::kAim;
  r.effectors[1].target_position = ik_rigs::WorldOf(skeleton_, skeleton_.rest).Position(skeleton_, "RightHand");
  EXPECT_EQ(ErrorOf(r), "effectors[1].target_position: at the origin of 'RightHand'; nothing to aim at");
  r = request_;
  r.solver = IkSolver::kFabrik;
  r.effectors.resize(1);
  r.free_root_translation = true;
  EXPECT_EQ(ErrorOf(r), "free_root_translation: only the dls solver translates the root");
  r = request_;
  r.solver = static_cast<IkSolver>(42);
  EXPECT_EQ(ErrorOf(r), "solver: unknown value 42");
}

TEST_F(IkValidationTest, Options) {
  IkRequest r = request_;
  r.options.max_iterations = -1;
  EXPECT_EQ(ErrorOf(r), "options.max_iterations: negative");
  r = request_;
  r.options.softness = 1.0;
  EXPECT_EQ(ErrorOf(r), "options.softness: must be in [0, 1)");
  r = request_;
  r.options.position_tolerance = NAN;
  EXPECT_EQ(ErrorOf(r), "options.position_tolerance: negative or not finite");
  r = request_;
  r.max_chain_depth = -2;
  EXPECT_EQ(ErrorOf(r), "max_chain_depth: negative");
  r = request_;
  r.free_joints = {"LeftArm"};
  EXPECT_EQ(ErrorOf(r), "free_joints: not combined with root or max_chain_depth");
  r = request_;
  r.effectors[0].target_position.reset();
  EXPECT_EQ(ErrorOf(r), "effectors[0]: needs a target_position or a target_rotation");
}

// A workspace that saw a failed request solves the next one normally.
TEST_F(IkValidationTest, WorkspaceRecoversAfterAnError) {
  IkRequest bad = request_;
  bad.effectors[1].joint = "Nope";
  EXPECT_FALSE(SolveIk(skeleton_, bad, ws_, result_).ok());
  ASSERT_TRUE(SolveIk(skeleton_, request_, ws_, result_).ok());
  IkWorkspace fresh;
  IkResult expected;
  ASSERT_TRUE(SolveIk(skeleton_, request_, fresh, expected).ok());
  ASSERT_EQ(result_.pose.size(), expected.pose.size());
  for (size_t j = 0; j < expected.pose.size(); ++j)
    EXPECT_TRUE(result_.pose[j].rotation.isApprox(expected.pose[j].rotation, 1e-12)) << j;
}

}  // namespace
}  // namespace armature
