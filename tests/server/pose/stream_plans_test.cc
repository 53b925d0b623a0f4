// StreamClip's plans without gRPC, over the demo catalog: a clip's frames
// (joints and skeleton named on the first only), a motion's unwrapped time,
// and what Make refuses.
#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "server/pose/clip_stream_plan.h"
#include "server/pose/motion_stream_plan.h"

namespace armature::server {
namespace {

using test_util::DemoCatalog;

class StreamPlans : public ::testing::Test {
 protected:
  std::shared_ptr<const Catalog> catalog_ = DemoCatalog();
  const Limits limits_;
  StreamPacing pacing_{10, 2, false, 0.5, 0};
};

TEST_F(StreamPlans, AClipNamesItsJointsAndSkeletonOnTheFirstFrameOnly) {
  v1::StreamClipRequest request;
  request.set_clip("demo_walk");
  request.add_joints("Hips");
  auto plan = ClipStreamPlan::Make(*catalog_, limits_, request, pacing_);
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  EXPECT_DOUBLE_EQ(plan->duration(), catalog_->FindClip("demo_walk")->part->runtime->duration);
  v1::PoseFrame first, second;
  ASSERT_TRUE(plan->Fill(0, 0.5, WrapMode::kClamp, first).ok());
  ASSERT_TRUE(plan->Fill(1, 0.7, WrapMode::kClamp, second).ok());
  EXPECT_EQ(first.skeleton(), "demo_walk");
  EXPECT_EQ(first.joints_size(), 1);
  EXPECT_DOUBLE_EQ(second.time(), 0.7);
  EXPECT_EQ(second.index(), 1u);
  EXPECT_TRUE(second.skeleton().empty());
  EXPECT_EQ(second.joints_size(), 0);
  EXPECT_EQ(second.pose().rotations_size(), 4);
}

TEST_F(StreamPlans, MakeRefusesUnknownClipsAndJoints) {
  v1::StreamClipRequest request;
  request.set_clip("nope");
  EXPECT_EQ(ClipStreamPlan::Make(*catalog_, limits_, request, pacing_).status().code(), StatusCode::kNotFound);
  request.set_clip("demo_walk");
  request.add_joints("NoSuchJoint");
  EXPECT_EQ(ClipStreamPlan::Make(*catalog_, limits_, request, pacing_).status().code(), StatusCode::kNotFound);
}

TEST_F(StreamPlans, AMotionPlaysUnwrappedTime) {
  v1::StreamClipRequest request;
  request.mutable_motion()->add_layers()->set_clip("demo_walk");
  auto plan = MotionStreamPlan::Make(*catalog_, limits_, request, pacing_);
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  v1::PoseFrame frame;
  ASSERT_TRUE(plan->Fill(0, 0, WrapMode::kLoop, frame).ok());
  EXPECT_EQ(frame.skeleton(), "demo_walk");
  frame.Clear();
  ASSERT_TRUE(plan->Fill(40, 0, WrapMode::kLoop, frame).ok());
  EXPECT_DOUBLE_EQ(frame.time(), 0.5 + 2 * 40 / 10.0);  // start_time + speed·k/fps, past the clip's end
}

}  // namespace
}  // namespace armature::server
