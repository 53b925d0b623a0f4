// CrowdService.CrowdSession against a real server on CMU 01_01 and
// RobotExpressive: the C++ client's decoded poses equal EvaluateClip's local
// poses at each character's clip time within the encoding's stated error
// plus the clip's compression bound, refused commands come back in a frame
// naming the character while the session runs on, and `armature crowd`
// keeps pace at under 8 bytes a joint.
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "armature/crowd_decoder.h"
#include "armature/v1/crowd.grpc.pb.h"
#include "crowd/crowd_commands.h"
#include "support/client_helpers.h"
#include "support/server_process.h"
#include "support/server_suite.h"

namespace armature::testing {
namespace {

// CMU's compression bound (0.01 units at a 3-unit shell, ErrorBound's default for a
// BVH body of its span) as a local rotation: a joint's error moves a shell point by
// at least its angle × 3, so its angle is under 0.01 / 3; twice that for margin.
constexpr double kCompressionAngle = 2 * 0.01 / 3;

class Crowd : public CmuAndRobotSuite {};

TEST_F(Crowd, DecodedPosesAreEvaluateClipsLocalPosesWithinTheStatedError) {
  client::Client client(OptionsFor(*server_));
  auto stub = v1::CrowdService::NewStub(client.channel());
  grpc::ClientContext context;
  client.Prepare(context, true);
  auto stream = stub->CrowdSession(&context);
  ASSERT_TRUE(stream->Write(StartCommand(0.5)));
  for (uint32_t id = 0; id < 40; ++id) ASSERT_TRUE(stream->Write(AddCommand(id, "cmu", 0.53 * id, 0.5 + 0.05 * id)));
  stream->WritesDone();
  client::CrowdDecoder decoder;
  v1::CrowdFrame frame;
  double worst_angle = 0, worst_translation = 0, stated = 0;
  size_t compared = 0, frames = 0;
  while (stream->Read(&frame)) {
    ++frames;
    const client::CrowdPoses poses = decoder.Decode(frame);
    ASSERT_EQ(frame.errors_size(), 0) << frame.errors(0).error();
    if (poses.ids.empty()) continue;
    stated = decoder.layout(frame.layouts(0))->max_rotation_error();
    v1::EvaluateClipRequest request;
    request.set_clip("cmu");
    request.set_space(v1::LOCAL);
    for (double t : poses.clip_times) request.add_times(t);
    const v1::EvaluateClipResponse evaluated = client.EvaluateClip(request);
    ASSERT_EQ(evaluated.poses_size(), static_cast<int>(poses.ids.size()));
    ASSERT_EQ(poses.joints, 31u);
    for (size_t i = 0; i < poses.ids.size(); ++i) {
      const v1::Pose& p = evaluated.poses(static_cast<int>(i));
      for (size_t j = 0; j < 31; ++j) {
        worst_angle = std::max(worst_angle, Angle(&poses.rotations[(i * 31 + j) * 4], &p.rotations()[j * 4]));
        for (int k = 0; k < 3; ++k)
          worst_translation = std::max(worst_translation, std::abs(double(poses.translations[(i * 31 + j) * 3 + k]) -
                                                                   p.translations()[j * 3 + k]));
      }
      ++compared;
    }
  }
  ASSERT_TRUE(stream->Finish().ok());
  EXPECT_EQ(frames, 15u);  // 0.5 s at 30 fps
  EXPECT_GE(compared, 40u);
  EXPECT_NEAR(stated, 1.495e-4, 1e-6);
  EXPECT_LE(worst_angle, stated + kCompressionAngle);
  EXPECT_LE(worst_translation, 0.02);  // the bound's 0.01 units at the hips, with float rounding
  std::printf("worst rotation difference %.3g rad (stated encoding error %.3g), translation %.3g units\n", worst_angle,
              stated, worst_translation);
}

TEST_F(Crowd, RefusedCommandsNameTheCharacterAndTheSessionRunsOn) {
  client::Client client(OptionsFor(*server_));
  const std::string robot_skeleton = RobotSkeleton(client);
  ASSERT_FALSE(robot_skeleton.empty());
  auto stub = v1::CrowdService::NewStub(client.channel());
  grpc::ClientContext context;
  client.Prepare(context, true);
  auto stream = stub->CrowdSession(&context);
  for (const v1::CrowdCommand& c : RefusedCommands(robot_skeleton)) ASSERT_TRUE(stream->Write(c));
  stream->WritesDone();
  std::vector<v1::CrowdError> errors;
  v1::CrowdFrame frame;
  size_t frames = 0, last_characters = 0;
  while (stream->Read(&frame)) {
    ++frames;
    errors.insert(errors.end(), frame.errors().begin(), frame.errors().end());
    last_characters = frame.stats().characters();
  }
  ASSERT_TRUE(stream->Finish().ok());
  EXPECT_EQ(frames, 12u);
  EXPECT_EQ(last_characters, 1u);
  ASSERT_EQ(errors.size(), 4u);
  const uint32_t ids[] = {1, 2, 3, 44};
  const int codes[] = {6, 3, 3, 5};
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(errors[i].id(), ids[i]);
    EXPECT_EQ(errors[i].code(), codes[i]) << errors[i].error();
    EXPECT_EQ(errors[i].error().rfind("character " + std::to_string(ids[i]) + ": ", 0), 0u) << errors[i].error();
  }
  EXPECT_NE(errors[1].error().find(robot_skeleton), std::string::npos) << errors[1].error();
}

TEST_F(Crowd, TheCliKeepsPaceInUnderEightBytesAJoint) {
  const CommandResult r = RunCli(
      server_->target(), {"crowd", "cmu", "cmu", "--characters", "500", "--fps", "30", "--seconds", "2", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream lines(r.out);
  nlohmann::json summary;
  size_t frames = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.empty()) continue;
    const nlohmann::json j = nlohmann::json::parse(line);
    if (j.contains("summary"))
      summary = j["summary"];
    else
      ++frames;
  }
  EXPECT_EQ(frames, 60u);
  ASSERT_TRUE(summary.is_object()) << r.out;
  EXPECT_EQ(summary["frames"], 60);
  EXPECT_NEAR(summary["meanTickIntervalMs"].get<double>(), 1000.0 / 30, 1000.0 / 30 * 0.05);
  EXPECT_LE(summary["poseBytesPerJoint"].get<double>(), 6.5);  // 31 × 6 + 12 bytes for 31 joints
  EXPECT_LE(summary["wireBytesPerJoint"].get<double>(), 8.0);
  std::printf("%s\n", summary.dump().c_str());
}

}  // namespace
}  // namespace armature::testing
