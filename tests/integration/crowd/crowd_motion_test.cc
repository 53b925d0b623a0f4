// CrowdService.CrowdSession with characters on a motion (issue 31) against a
// real server: RobotExpressive's Walking and Running blended 0.3 / 0.7. The
// C++ client's decoded poses equal EvaluateMotion's local poses at each
// character's motion time within the encoding's stated error (both blend the
// same stored clips with BlendMotionJob, so no compression term enters), and
// bad motions come back as CrowdErrors naming the character while the
// session runs on.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "armature/crowd_decoder.h"
#include "armature/v1/crowd.grpc.pb.h"
#include "crowd/crowd_commands.h"
#include "support/client_helpers.h"
#include "support/server_process.h"
#include "support/server_suite.h"

namespace armature::testing {
namespace {

// float32 on both sides (Pose and the decoder's arrays): well under the encoding's error.
constexpr double kFloatSlack = 1e-5;

class CrowdMotion : public CmuAndRobotSuite {};

v1::Motion TwoLayers(const std::string& a, double wa, const std::string& b, double wb) {
  v1::Motion motion;
  v1::MotionLayer* first = motion.add_layers();
  first->set_clip(a);
  first->set_weight(wa);
  v1::MotionLayer* second = motion.add_layers();
  second->set_clip(b);
  second->set_weight(wb);
  second->set_time_offset(0.25);
  return motion;
}

v1::CrowdCommand AddMotion(uint32_t id, const v1::Motion& motion, double offset, double speed) {
  v1::CrowdCommand c = AddCommand(id, "", offset, speed);
  *c.mutable_add()->mutable_motion() = motion;
  return c;
}

TEST_F(CrowdMotion, DecodedPosesAreEvaluateMotionsLocalPosesWithinTheStatedError) {
  client::Client client(OptionsFor(*server_));
  const v1::Motion motion = TwoLayers("robot.Walking", 0.3, "robot.Running", 0.7);
  auto stub = v1::CrowdService::NewStub(client.channel());
  grpc::ClientContext context;
  client.Prepare(context, true);
  auto stream = stub->CrowdSession(&context);
  ASSERT_TRUE(stream->Write(StartCommand(0.5)));
  for (uint32_t id = 0; id < 20; ++id) ASSERT_TRUE(stream->Write(AddMotion(id, motion, 0.37 * id, 0.5 + 0.1 * id)));
  stream->WritesDone();
  client::CrowdDecoder decoder;
  v1::CrowdFrame frame;
  double worst_angle = 0, worst_translation = 0, stated = 0, moved = 0;
  size_t compared = 0, frames = 0, layouts = 0;
  std::vector<float> first_pose;
  while (stream->Read(&frame)) {
    ++frames;
    layouts += frame.new_layouts_size();
    const client::CrowdPoses poses = decoder.Decode(frame);
    ASSERT_EQ(frame.errors_size(), 0) << frame.errors(0).error();
    if (poses.ids.empty()) continue;
    const v1::CrowdLayout* layout = decoder.layout(frame.layouts(0));
    EXPECT_EQ(layout->clip(), "motion:robot.Walking+robot.Running");
    stated = layout->max_rotation_error();
    v1::EvaluateMotionRequest request;
    *request.mutable_motion() = motion;
    request.set_space(v1::LOCAL);
    for (double t : poses.clip_times) request.add_times(t);
    const v1::EvaluateMotionResponse evaluated = client.EvaluateMotion(request);
    ASSERT_EQ(evaluated.poses_size(), static_cast<int>(poses.ids.size()));
    const size_t n = poses.joints;
    ASSERT_EQ(static_cast<size_t>(evaluated.joints_size()), n);
    if (first_pose.empty()) first_pose.assign(poses.rotations.begin(), poses.rotations.begin() + n * 4);
    for (size_t i = 0; i < poses.ids.size(); ++i) {
      const v1::Pose& p = evaluated.poses(static_cast<int>(i));
      for (size_t j = 0; j < n; ++j) {
        worst_angle = std::max(worst_angle, Angle(&poses.rotations[(i * n + j) * 4], &p.rotations()[j * 4]));
        moved = std::max(moved, Angle(&poses.rotations[(i * n + j) * 4], &first_pose[j * 4]));
        for (int k = 0; k < 3; ++k)
          worst_translation = std::max(worst_translation, std::abs(double(poses.translations[(i * n + j) * 3 + k]) -
                                                                   p.translations()[j * 3 + k]));
      }
      ++compared;
    }
  }
  ASSERT_TRUE(stream->Finish().ok());
  EXPECT_EQ(frames, 15u);  // 0.5 s at 30 fps
  EXPECT_EQ(layouts, 1u);  // one motion bound once for its 20 characters
  EXPECT_GE(compared, 20u);
  EXPECT_GT(moved, 0.1);  // the poses differ across characters and times: the comparison has teeth
  EXPECT_NEAR(stated, 1.495e-4, 1e-6);
  EXPECT_LE(worst_angle, stated + kFloatSlack);
  EXPECT_LE(worst_translation, 1e-4);
  std::printf("motion: %zu poses compared, worst rotation difference %.3g rad (stated %.3g), translation %.3g\n",
              compared, worst_angle, stated, worst_translation);
}

TEST_F(CrowdMotion, BadMotionsNameTheCharacterAndTheSessionRunsOn) {
  client::Client client(OptionsFor(*server_));
  const std::string robot_skeleton = RobotSkeleton(client);
  ASSERT_FALSE(robot_skeleton.empty());
  const v1::Motion good = TwoLayers("robot.Walking", 0.3, "robot.Running", 0.7);
  std::vector<v1::CrowdCommand> commands = {StartCommand(0.4), AddMotion(1, good, 0, 1)};
  commands.push_back(AddMotion(2, TwoLayers("robot.Walking", 0.3, "robot.NoSuchClip", 0.7), 0, 1));
  commands.push_back(AddMotion(3, TwoLayers("cmu", 0.5, "cmu", 0.5), 0, 1));  // CMU's joints on the robot
  commands.back().mutable_add()->set_skeleton(robot_skeleton);
  commands.push_back(AddMotion(4, TwoLayers("robot.Walking", 0.5, "cmu", 0.5), 0, 1));  // CMU lacks the robot's joints
  commands.push_back(AddMotion(5, TwoLayers("robot.Walking", std::nan(""), "robot.Running", 0.7), 0, 1));
  commands.push_back(AddMotion(6, good, 0, 1));
  commands.back().mutable_add()->set_clip("robot.Walking");  // both a clip and a motion
  commands.push_back(AddMotion(7, good, 0.5, 1));
  auto stub = v1::CrowdService::NewStub(client.channel());
  grpc::ClientContext context;
  client.Prepare(context, true);
  auto stream = stub->CrowdSession(&context);
  for (const v1::CrowdCommand& c : commands) ASSERT_TRUE(stream->Write(c));
  stream->WritesDone();
  std::vector<v1::CrowdError> errors;
  v1::CrowdFrame frame;
  size_t frames = 0, last_characters = 0, updated = 0;
  while (stream->Read(&frame)) {
    ++frames;
    errors.insert(errors.end(), frame.errors().begin(), frame.errors().end());
    last_characters = frame.stats().characters();
    updated += frame.ids_size();
  }
  ASSERT_TRUE(stream->Finish().ok());
  EXPECT_EQ(frames, 12u);
  EXPECT_EQ(last_characters, 2u);  // 1 and 7
  EXPECT_GE(updated, 20u);         // 2 characters over 12 ticks, the first ones staggered
  ASSERT_EQ(errors.size(), 5u);
  const uint32_t ids[] = {2, 3, 4, 5, 6};
  const int codes[] = {5, 3, 3, 3, 3};
  const char* names[] = {"NoSuchClip", robot_skeleton.c_str(), "motion", "weight", "clip and motion"};
  for (size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(errors[i].id(), ids[i]);
    EXPECT_EQ(errors[i].code(), codes[i]) << errors[i].error();
    EXPECT_EQ(errors[i].error().rfind("character " + std::to_string(ids[i]) + ": ", 0), 0u) << errors[i].error();
    EXPECT_NE(errors[i].error().find(names[i]), std::string::npos) << errors[i].error();
    std::printf("%s\n", errors[i].error().c_str());
  }
}

}  // namespace
}  // namespace armature::testing
