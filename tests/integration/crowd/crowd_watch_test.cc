// CrowdService.WatchCrowd, the read-only crowd, through the gRPC-Web gateway
// of a real server: every frame equals the one the same call sends over
// gRPC (wall-clock fields aside), and bad input fails the call before any
// frame with a status naming the character or the limit.
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "armature/client.h"
#include "armature/crowd_decoder.h"
#include "armature/v1/crowd.grpc.pb.h"
#include "gateway/grpc_web_call.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

constexpr char kPath[] = "/armature.v1.CrowdService/WatchCrowd";

v1::WatchCrowdRequest Watch(uint32_t characters, uint64_t ticks) {
  v1::WatchCrowdRequest request;
  request.mutable_start()->set_fps(30);
  request.set_max_ticks(ticks);
  for (uint32_t id = 0; id < characters; ++id) {
    v1::CrowdCharacter& c = *request.add_characters();
    c.set_id(id);
    c.set_clip("demo_walk");
    c.set_time_offset(0.11 * id);
    c.set_speed(0.5 + 0.1 * id);
  }
  return request;
}

class CrowdWatch : public ::testing::Test {
 protected:
  TempDir data_;
};

TEST_F(CrowdWatch, GrpcWebFramesEqualTheGrpcStreamsFrames) {
  ServerProcess server(data_.path());
  auto http = Http(server);
  client::Client grpc(OptionsFor(server));
  const v1::WatchCrowdRequest request = Watch(20, 10);
  std::vector<v1::CrowdFrame> expected;
  {
    grpc::ClientContext context;
    auto reader = v1::CrowdService::NewStub(grpc.channel())->WatchCrowd(&context, request);
    v1::CrowdFrame frame;
    while (reader->Read(&frame)) expected.push_back(frame);
    ASSERT_TRUE(reader->Finish().ok());
  }
  ASSERT_EQ(expected.size(), 10u);  // max_ticks
  for (const bool text : {false, true}) {
    SCOPED_TRACE(text ? "text" : "binary");
    const auto a = Call(http, kPath, Frame(request.SerializeAsString()), text);
    EXPECT_EQ(a.http_status, 200);
    EXPECT_EQ(a.code(), 0) << a.message();
    ASSERT_EQ(a.messages.size(), expected.size());
    client::CrowdDecoder decoder;
    size_t poses = 0;
    for (size_t i = 0; i < expected.size(); ++i) {
      v1::CrowdFrame got;
      ASSERT_TRUE(got.ParseFromString(a.messages[i]));
      // Wall-clock fields differ between two runs; the crowd must not.
      google::protobuf::util::MessageDifferencer diff;
      diff.IgnoreField(v1::CrowdFrame::descriptor()->FindFieldByName("wall_time"));
      diff.IgnoreField(v1::CrowdTickStats::descriptor()->FindFieldByName("work_ms"));
      diff.IgnoreField(v1::CrowdTickStats::descriptor()->FindFieldByName("late"));
      EXPECT_TRUE(diff.Compare(got, expected[i])) << i << ": " << got.ShortDebugString();
      EXPECT_EQ(got.tick(), i);
      const client::CrowdPoses decoded = decoder.Decode(got);
      poses += decoded.ids.size();
      for (size_t k = 0; k < decoded.ids.size(); ++k) {  // unit quaternions: the bytes decode as rotations
        const float* q = &decoded.rotations[(k * decoded.joints) * 4];
        EXPECT_NEAR(std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]), 1.0, 1e-5);
      }
    }
    EXPECT_GE(poses, 20u);  // every character at least once
  }
}

TEST_F(CrowdWatch, BadInputFailsBeforeAnyFrameWithAClearStatus) {
  ServerProcess server(data_.path(), {"--max-crowd-characters", "8"});
  auto http = Http(server);
  v1::WatchCrowdRequest nan = Watch(4, 5);
  nan.mutable_characters(3)->set_speed(std::nan(""));
  const auto a = Call(http, kPath, Frame(nan.SerializeAsString()));
  EXPECT_EQ(a.http_status, 200);
  EXPECT_TRUE(a.messages.empty());
  EXPECT_EQ(a.code(), 3);
  EXPECT_EQ(a.message().rfind("character 3: ", 0), 0u) << a.message();

  const auto over = Call(http, kPath, Frame(Watch(9, 5).SerializeAsString()), true);
  EXPECT_TRUE(over.messages.empty());
  EXPECT_EQ(over.code(), 8);
  EXPECT_NE(over.message().find("--max-crowd-characters"), std::string::npos) << over.message();

  v1::WatchCrowdRequest duplicate = Watch(3, 5);
  duplicate.mutable_characters(2)->set_id(1);
  const auto twice = Call(http, kPath, Frame(duplicate.SerializeAsString()));
  EXPECT_EQ(twice.code(), 6);
  EXPECT_EQ(twice.message().rfind("character 1: ", 0), 0u) << twice.message();

  v1::WatchCrowdRequest fps = Watch(2, 5);
  fps.mutable_start()->set_fps(std::nan(""));
  const auto bad_fps = Call(http, kPath, Frame(fps.SerializeAsString()));
  EXPECT_EQ(bad_fps.code(), 3);
  EXPECT_NE(bad_fps.message().find("start.fps"), std::string::npos) << bad_fps.message();

  // The server serves on: a good watch after the refusals.
  const auto good = Call(http, kPath, Frame(Watch(8, 3).SerializeAsString()));
  EXPECT_EQ(good.code(), 0) << good.message();
  EXPECT_EQ(good.messages.size(), 3u);
}

}  // namespace
}  // namespace armature::testing
