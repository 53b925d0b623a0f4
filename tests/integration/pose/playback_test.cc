// PlaybackSession end to end on a real server: a crossfade from Walking to
// Running on RobotExpressive is, at every frame, EvaluateMotion of the
// two-layer motion with the linearly ramped weight; pause holds the pose,
// seek jumps, resume goes on; bad commands end the stream naming the field;
// sessions count against the session limits; the REST batch mapping.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "common/sse_events.h"
#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/metrics_scrape.h"
#include "support/server_process.h"
#include "support/server_suite.h"

namespace armature::testing {
namespace {
using nlohmann::json;

constexpr double kFps = 30;

// One open session over the generated stub.
struct Session {
  explicit Session(client::Client& client) : stub(v1::PoseService::NewStub(client.channel())) {
    stream = stub->PlaybackSession(&context);
  }
  bool Send(const v1::PlaybackCommand& c) { return stream->Write(c); }
  v1::PlaybackFrame Next() {
    v1::PlaybackFrame f;
    EXPECT_TRUE(stream->Read(&f)) << "the stream ended early";
    return f;
  }
  grpc::Status Close() {  // closes our side and reads what is left
    stream->WritesDone();
    v1::PlaybackFrame f;
    while (stream->Read(&f)) {}
    return stream->Finish();
  }
  grpc::Status Failure() {  // the server ends the stream
    v1::PlaybackFrame f;
    while (stream->Read(&f)) {}
    return stream->Finish();
  }
  std::unique_ptr<v1::PoseService::Stub> stub;
  grpc::ClientContext context;
  std::unique_ptr<grpc::ClientReaderWriter<v1::PlaybackCommand, v1::PlaybackFrame>> stream;
};

v1::PlaybackCommand Start(const std::string& skeleton, const std::string& clip) {
  v1::PlaybackCommand c;
  c.mutable_start()->set_skeleton(skeleton);
  c.mutable_start()->set_fps(kFps);
  if (!clip.empty()) c.mutable_start()->mutable_play()->set_clip(clip);
  return c;
}

v1::PlaybackCommand Play(const std::string& clip, double crossfade) {
  v1::PlaybackCommand c;
  c.mutable_play()->set_clip(clip);
  c.mutable_play()->set_crossfade(crossfade);
  return c;
}

// A layer of an EvaluateMotion request at time 0: `clip` at clip time `time`.
void AddLayer(v1::EvaluateMotionRequest& r, const std::string& clip, double weight, double time) {
  v1::MotionLayer* l = r.mutable_motion()->add_layers();
  l->set_clip(clip);
  l->set_weight(weight);
  l->set_time_offset(time);
}

// The largest difference of two poses' values, relative to the value beyond
// 1 (the poses travel as floats: a translation of 300 has steps of 3e-5).
double MaxDifference(const v1::Pose& a, const v1::Pose& b) {
  auto diff = [](float x, float y) { return std::abs(double{x} - y) / std::max(1.0, std::abs(double{y})); };
  double d = 0;
  EXPECT_EQ(a.translations_size(), b.translations_size());
  EXPECT_EQ(a.rotations_size(), b.rotations_size());
  for (int i = 0; i < std::min(a.translations_size(), b.translations_size()); ++i)
    d = std::max(d, diff(a.translations(i), b.translations(i)));
  for (int i = 0; i < std::min(a.rotations_size(), b.rotations_size()); ++i)
    d = std::max(d, diff(a.rotations(i), b.rotations(i)));
  return d;
}

class Playback : public ServerSuite {
 protected:
  static void SetUpTestSuite() {
    ServerSuite::SetUpTestSuite();
    client::Client(OptionsFor(*server_)).ImportFile(WriteTemp(*data_, "arm.bvh", kArmBvh), "arm");
    const std::string glb = SharedData("gltf/RobotExpressive/RobotExpressive.glb");
    if (glb.empty()) return;
    client::Client client(OptionsFor(*server_));
    const auto imported = client.ImportFile(glb, "robot");
    for (const auto& clip : imported.asset().clips()) {
      const std::string& n = clip.name();
      if (n.size() >= 7 && n.substr(n.size() - 7) == "Walking") walking_ = n, skeleton_ = clip.skeleton();
      if (n.size() >= 7 && n.substr(n.size() - 7) == "Running") running_ = n;
    }
  }
  void RequireRobot() {
    if (walking_.empty() || running_.empty())
      GTEST_SKIP() << "RobotExpressive.glb (Walking, Running) not found in the shared data (ARMATURE_SHARED_DATA)";
  }
  static v1::Pose Evaluate(v1::EvaluateMotionRequest r) {
    client::Client client(OptionsFor(*server_));
    r.add_times(0);
    r.set_space(v1::LOCAL);
    return client.EvaluateMotion(r).poses(0);
  }
  static inline std::string walking_, running_, skeleton_;
};

TEST_F(Playback, CrossfadeFromWalkingToRunningIsTheRampedTwoLayerBlendAtEveryFrame) {
  RequireRobot();
  if (IsSkipped()) return;  // GTEST_SKIP in a helper returns from the helper only
  client::Client client(OptionsFor(*server_));
  Session s(client);
  ASSERT_TRUE(s.Send(Start(skeleton_, walking_)));
  std::vector<v1::PlaybackFrame> frames;
  for (int i = 0; i < 8; ++i) frames.push_back(s.Next());
  ASSERT_TRUE(s.Send(Play(running_, 0.5)));
  // The frame the play applied to: the first with a second motion. The fade
  // takes 15 frames at 30 fps; read 10 past it.
  size_t fade = 0;
  while (frames.size() < 300 && (fade == 0 || frames.size() < fade + 25)) {
    frames.push_back(s.Next());
    if (fade == 0 && frames.back().motions_size() > 1) fade = frames.size() - 1;
  }
  EXPECT_TRUE(s.Close().ok());
  EXPECT_EQ(frames[0].skeleton(), skeleton_);
  ASSERT_GE(fade, 8u) << "the play command never applied";
  const double fade_start = frames[fade].time();
  int in_fade = 0;
  double mid_fade_change = 0;  // how far a mid-fade pose is from Walking alone
  double worst = 0;            // the largest difference from EvaluateMotion
  for (size_t i = 0; i < frames.size(); ++i) {
    SCOPED_TRACE("frame " + std::to_string(i));
    const v1::PlaybackFrame& f = frames[i];
    ASSERT_EQ(f.index(), i);
    const double t = static_cast<double>(i) / kFps;
    EXPECT_NEAR(f.time(), t, 1e-12) << "session time advances by exactly 1/fps";
    const double run_time = t - fade_start, a = run_time / 0.5;
    v1::EvaluateMotionRequest want;
    if (i < fade) {
      ASSERT_EQ(f.motions_size(), 1);
      EXPECT_EQ(f.motions(0).name(), walking_);
      EXPECT_NEAR(f.motions(0).weight(), 1.0, 1e-12);
      EXPECT_NEAR(f.motions(0).time(), t, 1e-9);
      AddLayer(want, walking_, 1, t);
    } else if (a < 1 - 1e-9) {
      ++in_fade;
      ASSERT_EQ(f.motions_size(), 2);
      EXPECT_EQ(f.motions(0).id(), 0u);
      EXPECT_EQ(f.motions(1).id(), 1u);
      EXPECT_EQ(f.motions(1).name(), running_);
      EXPECT_NEAR(f.motions(0).weight(), 1 - a, 1e-9);
      EXPECT_NEAR(f.motions(1).weight(), a, 1e-9);
      EXPECT_NEAR(f.motions(0).time(), t, 1e-9) << "Walking keeps running";
      EXPECT_NEAR(f.motions(1).time(), run_time, 1e-9) << "Running starts at its time 0";
      AddLayer(want, walking_, 1 - a, t);
      AddLayer(want, running_, a, run_time);
    } else {
      ASSERT_EQ(f.motions_size(), 1) << "Walking stops when its fade-out is complete";
      EXPECT_EQ(f.motions(0).name(), running_);
      EXPECT_NEAR(f.motions(0).weight(), 1.0, 1e-12);
      EXPECT_NEAR(f.motions(0).time(), run_time, 1e-9);
      AddLayer(want, running_, 1, run_time);
    }
    const double difference = MaxDifference(f.pose(), Evaluate(want));
    EXPECT_LT(difference, 1e-5);
    worst = std::max(worst, difference);
    if (i == fade + 7) {
      v1::EvaluateMotionRequest walk_only;
      AddLayer(walk_only, walking_, 1, t);
      mid_fade_change = MaxDifference(f.pose(), Evaluate(walk_only));
    }
  }
  EXPECT_EQ(in_fade, 15);
  EXPECT_GT(mid_fade_change, 1e-2) << "half way through the fade the pose is not Walking's";
  std::printf(
      "  fade applied at frame %zu (session time %.4f s); %d frames inside it; mid-fade change %.4f; "
      "largest difference from EvaluateMotion over %zu frames %.3g\n",
      fade, fade_start, in_fade, mid_fade_change, frames.size(), worst);
}

TEST_F(Playback, PauseHoldsThePoseSeekJumpsResumeGoesOn) {
  RequireRobot();
  if (IsSkipped()) return;  // GTEST_SKIP in a helper returns from the helper only
  client::Client client(OptionsFor(*server_));
  Session s(client);
  ASSERT_TRUE(s.Send(Start(skeleton_, walking_)));
  for (int i = 0; i < 3; ++i) s.Next();
  v1::PlaybackCommand pause;
  pause.mutable_pause();
  ASSERT_TRUE(s.Send(pause));
  v1::PlaybackFrame f = s.Next();
  while (!f.paused()) f = s.Next();
  const double held = f.motions(0).time();
  const v1::Pose held_pose = f.pose();
  for (int i = 0; i < 5; ++i) {
    const v1::PlaybackFrame p = s.Next();
    EXPECT_TRUE(p.paused());
    EXPECT_NEAR(p.time(), static_cast<double>(p.index()) / kFps, 1e-12) << "the session clock goes on";
    EXPECT_EQ(p.motions(0).time(), held) << "the motion's time stands";
    EXPECT_EQ(MaxDifference(p.pose(), held_pose), 0);
  }
  v1::PlaybackCommand seek;
  seek.mutable_seek()->set_time(0.25);
  ASSERT_TRUE(s.Send(seek));
  f = s.Next();
  while (f.motions(0).time() == held) f = s.Next();
  EXPECT_NEAR(f.motions(0).time(), 0.25, 1e-12);
  v1::EvaluateMotionRequest at_seek;
  AddLayer(at_seek, walking_, 1, 0.25);
  EXPECT_LT(MaxDifference(f.pose(), Evaluate(at_seek)), 1e-5);
  v1::PlaybackCommand resume;
  resume.mutable_resume();
  ASSERT_TRUE(s.Send(resume));
  f = s.Next();
  while (f.paused()) f = s.Next();
  // The first frame after resume still shows 0.25; each later one 1/fps on.
  const uint64_t resumed = f.index();
  EXPECT_NEAR(f.motions(0).time(), 0.25, 1e-12);
  for (int i = 0; i < 5; ++i) {
    f = s.Next();
    const double want = 0.25 + static_cast<double>(f.index() - resumed) / kFps;
    EXPECT_NEAR(f.motions(0).time(), want, 1e-9);
    v1::EvaluateMotionRequest r;
    AddLayer(r, walking_, 1, want);
    EXPECT_LT(MaxDifference(f.pose(), Evaluate(r)), 1e-5);
  }
  EXPECT_TRUE(s.Close().ok());
}

// Layer weight and speed on the demo walk (always there): applied at the
// next frame, the speed without a jump in the layer's time.
TEST_F(Playback, LayerWeightAndSpeedApplyAtTheNextFrame) {
  client::Client client(OptionsFor(*server_));
  Session s(client);
  ASSERT_TRUE(s.Send(Start("demo_walk", "demo_walk")));
  for (int i = 0; i < 3; ++i) s.Next();
  v1::PlaybackCommand c;
  c.mutable_set_layer()->set_layer(0);
  c.mutable_set_layer()->set_weight(0.5);
  c.mutable_set_layer()->set_speed(2);
  ASSERT_TRUE(s.Send(c));
  // Before the command: the walk at session time; from the frame it applies
  // to, the layer's time is t0 + 2·(t − t0) with weight 0.5 (the rest fills the other half).
  std::vector<v1::PlaybackFrame> frames;
  for (int i = 0; i < 12; ++i) frames.push_back(s.Next());
  EXPECT_TRUE(s.Close().ok());
  size_t applied = 0;
  for (; applied < frames.size(); ++applied) {
    v1::EvaluateMotionRequest walk;
    AddLayer(walk, "demo_walk", 1, frames[applied].time());
    if (MaxDifference(frames[applied].pose(), Evaluate(walk)) > 1e-3) break;
  }
  ASSERT_LT(applied, frames.size() - 3) << "the command never applied";
  const double t0 = frames[applied].time();
  for (size_t i = applied; i < frames.size(); ++i) {
    v1::EvaluateMotionRequest r;
    AddLayer(r, "demo_walk", 0.5, t0 + 2 * (frames[i].time() - t0));
    EXPECT_LT(MaxDifference(frames[i].pose(), Evaluate(r)), 1e-5) << "frame " << i;
  }
}

TEST_F(Playback, BadCommandsEndTheStreamNamingTheField) {
  client::Client client(OptionsFor(*server_));
  auto expect = [&](std::vector<v1::PlaybackCommand> commands, grpc::StatusCode code, std::vector<std::string> parts) {
    Session s(client);
    for (const auto& c : commands) s.Send(c);
    const grpc::Status st = s.Failure();
    EXPECT_EQ(st.error_code(), code) << st.error_message();
    for (const auto& p : parts) EXPECT_NE(st.error_message().find(p), std::string::npos) << st.error_message();
  };
  v1::PlaybackCommand pause;
  pause.mutable_pause();
  expect({pause}, grpc::StatusCode::INVALID_ARGUMENT, {"start: required in the first message"});
  expect({Start("demo_walk", "no_such_clip")}, grpc::StatusCode::NOT_FOUND, {"start.play.clip", "no_such_clip"});
  expect({Start("no_such_skeleton", "")}, grpc::StatusCode::NOT_FOUND, {"start.skeleton", "no_such_skeleton"});
  v1::PlaybackCommand fast = Start("demo_walk", "demo_walk");
  fast.mutable_start()->set_fps(1000);
  expect({fast}, grpc::StatusCode::INVALID_ARGUMENT, {"start.fps"});
  v1::PlaybackCommand layer;
  layer.mutable_set_layer()->set_layer(3);
  layer.mutable_set_layer()->set_weight(0.5);
  expect({Start("demo_walk", "demo_walk"), layer}, grpc::StatusCode::INVALID_ARGUMENT,
         {"message 1: set_layer.layer: 3 is out of range"});
  v1::PlaybackCommand heavy;
  v1::MotionLayer* l = heavy.mutable_play()->mutable_motion()->add_layers();
  l->set_clip("demo_walk");
  l->set_weight(2);
  expect({Start("demo_walk", "demo_walk"), pause, heavy}, grpc::StatusCode::INVALID_ARGUMENT,
         {"message 2: play.motion.layers[0]", "weight"});
  v1::PlaybackCommand seek;
  seek.mutable_seek()->set_time(-1);
  expect({Start("demo_walk", "demo_walk"), seek}, grpc::StatusCode::INVALID_ARGUMENT, {"message 1: seek.time"});
  expect({Start("demo_walk", "demo_walk"), Start("demo_walk", "")}, grpc::StatusCode::INVALID_ARGUMENT,
         {"message 1: start: only in the first message"});
  // The arm is another skeleton: its clip cannot play in a demo_walk session.
  expect({Start("demo_walk", "demo_walk"), Play("arm", 0.5)}, grpc::StatusCode::INVALID_ARGUMENT,
         {"message 1: play.", "not the session's"});
  EXPECT_TRUE(client.Healthy());
}

TEST_F(Playback, SessionsCountAgainstTheSessionLimits) {
  TempDir data;
  ServerProcess server(data.path(), {"--max-sessions-per-client", "1"});
  client::Client client(OptionsFor(server));
  Session first(client);
  ASSERT_TRUE(first.Send(Start("demo_walk", "demo_walk")));
  first.Next();
  EXPECT_EQ(ScrapeSample(server, "armature_sessions_active{kind=\"playback\"}"), 1);
  Session second(client);
  second.Send(Start("demo_walk", "demo_walk"));
  const grpc::Status refused = second.Failure();
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(refused.error_message().find("--max-sessions-per-client"), std::string::npos) << refused.error_message();
  EXPECT_NE(refused.error_message().find("PlaybackSession"), std::string::npos) << refused.error_message();
  EXPECT_TRUE(first.Close().ok());
  EXPECT_TRUE(WaitFor([&] { return ScrapeSample(server, "armature_sessions_active{kind=\"playback\"}") == 0; }, 10));
}

// The gateway maps the session as a batch: NDJSON commands in, one SSE event
// per frame out; the start's duration ends it.
TEST_F(Playback, RestBatchPlaysForTheStartsDuration) {
  httplib::Client http("127.0.0.1", server_->http_port());
  const std::string body =
      json({{"start", {{"fps", 30}, {"duration", 0.2}, {"play", {{"clip", "demo_walk"}}}}}}).dump() + "\n";
  const auto r = http.Post("/v1/skeletons/demo_walk:playbackSession", body, "application/x-ndjson");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const std::vector<SseEvent> events = ParseSse(r->body);
  ASSERT_EQ(events.size(), 7u) << r->body.substr(0, 500);  // frames 0..5 (0.2 s at 30 fps), then the status
  for (int i = 0; i < 6; ++i) {
    const json frame = json::parse(events[i].data);
    EXPECT_NEAR(frame["time"].get<double>(), i / 30.0, 1e-12);
    EXPECT_EQ(frame["motions"][0]["name"], "demo_walk");
  }
  EXPECT_EQ(json::parse(events[0].data)["skeleton"], "demo_walk");
  EXPECT_EQ(events.back().event, "status");
  EXPECT_EQ(json::parse(events.back().data)["code"], 0);
}

}  // namespace
}  // namespace armature::testing
