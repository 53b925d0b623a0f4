// CrowdService.CrowdSession over a WebSocket on its REST path,
// /v1/crowds:session, against a real server on CMU 01_01 and RobotExpressive:
// in JSON text frames (`poses` in base64) and in binary frames, each pose
// equals the gRPC session's pose of the same character at the same clip time
// byte for byte; refused commands come back as the gRPC session's CrowdErrors
// while the session runs on, and it ends with a normal close.
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "armature/v1/crowd.grpc.pb.h"
#include "crowd/crowd_commands.h"
#include "support/client_helpers.h"
#include "support/server_process.h"
#include "support/server_suite.h"
#include "support/ws_client.h"

namespace armature::testing {
namespace {

constexpr int kText = 0x1, kBinary = 0x2, kClose = 0x8;

class CrowdWebSocket : public CmuAndRobotSuite {};

// A pose on the wire: (character, clip time) → its bytes, over a session's frames.
using PoseKey = std::tuple<uint32_t, double>;

std::map<PoseKey, std::string> PosesOf(const std::vector<v1::CrowdFrame>& frames) {
  std::map<PoseKey, std::string> poses;
  for (const v1::CrowdFrame& f : frames) {
    if (f.ids_size() == 0) continue;
    const size_t bytes = f.poses().size() / static_cast<size_t>(f.ids_size());
    for (int i = 0; i < f.ids_size(); ++i)
      poses[{f.ids(i), f.clip_times(i)}] = f.poses().substr(static_cast<size_t>(i) * bytes, bytes);
  }
  return poses;
}

std::vector<v1::CrowdFrame> GrpcSession(client::Client& client, const std::vector<v1::CrowdCommand>& commands) {
  auto stub = v1::CrowdService::NewStub(client.channel());
  grpc::ClientContext context;
  client.Prepare(context, true);
  auto stream = stub->CrowdSession(&context);
  for (const v1::CrowdCommand& c : commands) EXPECT_TRUE(stream->Write(c));
  stream->WritesDone();
  std::vector<v1::CrowdFrame> frames;
  for (v1::CrowdFrame f; stream->Read(&f);) frames.push_back(f);
  EXPECT_TRUE(stream->Finish().ok());
  return frames;
}

struct WsSession {
  std::vector<v1::CrowdFrame> frames;
  std::vector<nlohmann::json> json;  // the text frames as sent, in JSON mode
  int close_code = -1;
};

// The commands in text frames (protobuf's JSON) or binary frames, then every
// frame until the server closes (the start's duration ends the session).
WsSession WebSocketSession(int http_port, const std::vector<v1::CrowdCommand>& commands, bool binary) {
  WsSession s;
  WsClient ws(http_port, "/v1/crowds:session");
  EXPECT_EQ(ws.status(), 101) << ws.body();
  if (ws.status() != 101) return s;
  for (const v1::CrowdCommand& c : commands) {
    std::string payload;
    if (binary) {
      payload = c.SerializeAsString();
    } else {
      EXPECT_TRUE(google::protobuf::util::MessageToJsonString(c, &payload).ok());
    }
    ws.Send(binary ? kBinary : kText, payload);
  }
  for (Frame f = ws.Receive(); f.opcode != -1; f = ws.Receive()) {
    if (f.opcode == kClose) {
      s.close_code = f.close_code();
      break;
    }
    EXPECT_EQ(f.opcode, binary ? kBinary : kText) << f.payload.substr(0, 200);
    v1::CrowdFrame frame;
    if (binary) {
      EXPECT_TRUE(frame.ParseFromString(f.payload));
    } else {
      s.json.push_back(nlohmann::json::parse(f.payload));
      EXPECT_TRUE(google::protobuf::util::JsonStringToMessage(f.payload, &frame).ok()) << f.payload.substr(0, 200);
    }
    s.frames.push_back(std::move(frame));
  }
  return s;
}

TEST_F(CrowdWebSocket, JsonAndBinaryFramesCarryTheGrpcSessionsPosesByteForByte) {
  client::Client client(OptionsFor(*server_));
  std::vector<v1::CrowdCommand> commands = {StartCommand(0.5)};
  for (uint32_t id = 0; id < 12; ++id) commands.push_back(AddCommand(id, "cmu", 0.37 * id, 0.5 + 0.1 * id));
  const std::map<PoseKey, std::string> grpc_poses = PosesOf(GrpcSession(client, commands));
  ASSERT_GE(grpc_poses.size(), 12u);
  for (const bool binary : {false, true}) {
    SCOPED_TRACE(binary ? "binary frames" : "JSON text frames");
    const WsSession ws = WebSocketSession(server_->http_port(), commands, binary);
    EXPECT_EQ(ws.frames.size(), 15u);  // 0.5 s at 30 ticks a second
    EXPECT_EQ(ws.close_code, 1000);
    size_t matched = 0, updated = 0;
    for (const auto& [key, bytes] : PosesOf(ws.frames)) {
      ++updated;
      const auto it = grpc_poses.find(key);
      if (it == grpc_poses.end()) continue;
      ++matched;
      EXPECT_EQ(bytes, it->second) << "character " << std::get<0>(key) << " at clip time " << std::get<1>(key);
    }
    EXPECT_GE(updated, 12u * 10);
    EXPECT_GE(matched, updated * 9 / 10) << "the two sessions sampled different clip times";
    // The frame that first updates characters brings CMU's layout.
    size_t first = 0;
    while (first < ws.frames.size() && ws.frames[first].ids_size() == 0) ++first;
    ASSERT_LT(first, ws.frames.size());
    ASSERT_EQ(ws.frames[first].new_layouts_size(), 1);
    EXPECT_EQ(ws.frames[first].new_layouts(0).pose_bytes(), 31u * 6 + 12);
    if (!binary) {  // bytes travel as protobuf's JSON has them: base64
      const nlohmann::json& j = ws.json[first];
      ASSERT_TRUE(j.contains("poses")) << j.dump().substr(0, 300);
      EXPECT_TRUE(j["poses"].is_string());
      EXPECT_TRUE(j["stats"]["budgetMs"].is_number());
    }
  }
}

TEST_F(CrowdWebSocket, RefusedCommandsAreTheGrpcSessionsCrowdErrorsAndTheSessionRunsOn) {
  client::Client client(OptionsFor(*server_));
  const std::string robot_skeleton = RobotSkeleton(client);
  ASSERT_FALSE(robot_skeleton.empty());
  const std::vector<v1::CrowdCommand> commands = RefusedCommands(robot_skeleton);
  std::vector<v1::CrowdError> grpc_errors;
  for (const v1::CrowdFrame& f : GrpcSession(client, commands))
    grpc_errors.insert(grpc_errors.end(), f.errors().begin(), f.errors().end());
  ASSERT_EQ(grpc_errors.size(), 4u);
  // NaN travels in JSON as the string "NaN", as protobuf's JSON writes it.
  const WsSession ws = WebSocketSession(server_->http_port(), commands, /*binary=*/false);
  EXPECT_EQ(ws.frames.size(), 12u);  // 0.4 s at 30 ticks a second: the session ran on
  EXPECT_EQ(ws.close_code, 1000);
  std::vector<v1::CrowdError> errors;
  for (const v1::CrowdFrame& f : ws.frames) errors.insert(errors.end(), f.errors().begin(), f.errors().end());
  ASSERT_EQ(errors.size(), grpc_errors.size());
  const uint32_t ids[] = {1, 2, 3, 44};
  const int codes[] = {6, 3, 3, 5};
  for (size_t i = 0; i < errors.size(); ++i) {
    EXPECT_EQ(errors[i].id(), ids[i]);
    EXPECT_EQ(errors[i].code(), codes[i]) << errors[i].error();
    EXPECT_EQ(errors[i].message(), grpc_errors[i].message());
    EXPECT_EQ(errors[i].error(), grpc_errors[i].error());
  }
  ASSERT_FALSE(ws.frames.empty());
  EXPECT_EQ(ws.frames.back().stats().characters(), 1u);
}

}  // namespace
}  // namespace armature::testing
