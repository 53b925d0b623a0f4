// The IK session's logic without gRPC, over the demo catalog: the first
// message must start it, later ones move targets and are warm-started, and
// every refusal names the field as the client sees it.
#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "server/ik/ik_session.h"

namespace armature::server {
namespace {

using test_util::DemoCatalog;

v1::IkSessionRequest StartOn(const std::string& skeleton) {
  v1::IkSessionRequest r;
  r.mutable_start()->set_skeleton(skeleton);
  v1::IkEffector* e = r.mutable_start()->add_effectors();
  e->set_joint("LeftWrist");
  for (double v : {30.0, 120.0, 20.0}) e->add_target_position(v);
  return r;
}

v1::IkSessionRequest MoveTo(int effector, double x, double y, double z) {
  v1::IkSessionRequest r;
  v1::IkTargetUpdate* u = r.add_targets();
  u->set_effector(effector);
  for (double v : {x, y, z}) u->add_target_position(v);
  return r;
}

class IkSessionLogic : public ::testing::Test {
 protected:
  std::shared_ptr<const Catalog> catalog_ = DemoCatalog();
  const Limits limits_;
  IkSession session_{[this] { return catalog_; }, limits_};
  v1::SolveIkResponse response_;
};

TEST_F(IkSessionLogic, AnswersTheStartThenEachMove) {
  ASSERT_TRUE(session_.Start({}, StartOn("demo_walk"), &response_).ok());
  EXPECT_EQ(response_.skeleton(), "demo_walk");
  ASSERT_EQ(response_.residuals_size(), 1);
  EXPECT_EQ(response_.residuals(0).joint(), "LeftWrist");
  const int joints = response_.joints_size();
  EXPECT_GT(joints, 0);
  for (int k = 1; k <= 3; ++k) {
    const Status st = session_.Answer(MoveTo(0, 30.0 + k, 120.0, 20.0), &response_);
    ASSERT_TRUE(st.ok()) << st.message();
    EXPECT_EQ(response_.joints_size(), joints);  // each answer is whole, not appended to
    ASSERT_EQ(response_.residuals_size(), 1);
  }
}

TEST_F(IkSessionLogic, TheFirstMessageMustStartIt) {
  const Status missing = session_.Start({}, MoveTo(0, 1, 2, 3), &response_);
  EXPECT_EQ(missing.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(missing.message().rfind("start: required", 0), 0u) << missing.message();

  v1::IkSessionRequest both = StartOn("demo_walk");
  *both.add_targets() = MoveTo(0, 1, 2, 3).targets(0);
  const Status targets = session_.Start({}, both, &response_);
  EXPECT_EQ(targets.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(targets.message().rfind("targets: not in the first message", 0), 0u) << targets.message();
}

TEST_F(IkSessionLogic, ErrorsNameTheMessageAndField) {
  const Status unknown = session_.Start({}, StartOn("nope"), &response_);
  EXPECT_EQ(unknown.code(), StatusCode::kNotFound);
  EXPECT_EQ(unknown.message().rfind("start.", 0), 0u) << unknown.message();

  ASSERT_TRUE(session_.Start({}, StartOn("demo_walk"), &response_).ok());
  const Status again = session_.Answer(StartOn("demo_walk"), &response_);
  EXPECT_EQ(again.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(again.message(), "message 1: start: only in the first message");

  const Status bad = session_.Answer(MoveTo(5, 1, 2, 3), &response_);
  EXPECT_EQ(bad.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(bad.message().rfind("message 1: ", 0), 0u) << bad.message();
}

TEST_F(IkSessionLogic, ACancelledCallStopsTheSolveNamingNoField) {
  CallStop stop;
  stop.cancelled = [] { return true; };
  const Status st = session_.Start(stop, StartOn("demo_walk"), &response_);
  EXPECT_EQ(st.code(), StatusCode::kCancelled);
  EXPECT_NE(st.message().rfind("start.", 0), 0u) << st.message();
}

}  // namespace
}  // namespace armature::server
