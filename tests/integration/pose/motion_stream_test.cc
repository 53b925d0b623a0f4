// StreamClip with a motion instead of a clip, on a real server: each frame is
// EvaluateMotion at the frame's time; with EXTRACT each frame carries the
// root's motion since the previous frame; clip and motion are exclusive.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "armature/engine/io/demo_walk.h"
#include "support/client_helpers.h"
#include "support/server_process.h"
#include "support/server_suite.h"

namespace armature::testing {
namespace {

class MotionStream : public ServerSuite {
 protected:
  // Walk and the same walk 0.5 s later at weight 0.5 (a real blend), looping.
  static v1::Motion TwoLayers(v1::Motion::RootMotion mode) {
    v1::Motion m;
    m.add_layers()->set_clip("demo_walk");
    v1::MotionLayer* second = m.add_layers();
    second->set_clip("demo_character.walk");
    second->set_time_offset(0.5);
    second->set_weight(0.5);
    m.set_root_motion(mode);
    return m;
  }
  static std::vector<v1::PoseFrame> Stream(const v1::StreamClipRequest& r) {
    std::vector<v1::PoseFrame> frames;
    client::Client(OptionsFor(*server_)).StreamClip(r, [&](const v1::PoseFrame& f) {
      frames.push_back(f);
      return true;
    });
    return frames;
  }
};

// Streamed past the first layer's end (3 s) with loop: frame times are
// motion times (not wrapped), and every pose is EvaluateMotion's at that time.
TEST_F(MotionStream, EachFrameIsEvaluateMotionAtItsTime) {
  v1::StreamClipRequest r;
  *r.mutable_motion() = TwoLayers(v1::Motion::ACCUMULATE);
  r.set_fps(240);
  r.set_speed(8);
  r.set_start_time(2.5);
  r.set_duration(0.2);
  r.set_loop(true);
  r.set_space(v1::WORLD);
  const auto frames = Stream(r);
  ASSERT_GE(frames.size(), 40u);
  EXPECT_EQ(frames[0].skeleton(), "demo_walk");
  EXPECT_EQ(frames[0].joints_size(), 19);
  EXPECT_FALSE(frames[0].has_root_delta());
  v1::EvaluateMotionRequest e;
  *e.mutable_motion() = r.motion();
  e.set_space(v1::WORLD);
  for (const auto& f : frames) e.add_times(f.time());
  const auto want = client::Client(OptionsFor(*server_)).EvaluateMotion(e);
  ASSERT_EQ(want.poses_size(), static_cast<int>(frames.size()));
  for (size_t k = 0; k < frames.size(); ++k) {
    EXPECT_NEAR(frames[k].time(), 2.5 + 8.0 * static_cast<double>(k) / 240, 1e-9) << k;
    const auto& got = frames[k].pose();
    ASSERT_EQ(got.translations_size(), want.poses(k).translations_size());
    for (int i = 0; i < got.translations_size(); ++i) ASSERT_EQ(got.translations(i), want.poses(k).translations(i));
    for (int i = 0; i < got.rotations_size(); ++i) ASSERT_EQ(got.rotations(i), want.poses(k).rotations(i));
  }
  // Past 3 s (the loop point) ACCUMULATE walks on: the root keeps advancing along +Z.
  EXPECT_GT(frames.back().time(), 3.5);
  EXPECT_GT(frames.back().pose().translations(2), frames.front().pose().translations(2) + 0.5 * kDemoWalkSpeed);
}

// EXTRACT: the poses are IN_PLACE's, and the frames' root deltas add up to the
// root motion EvaluateMotion reports between the first frame and each frame.
TEST_F(MotionStream, ExtractFramesCarryTheRootDeltaSinceThePreviousFrame) {
  v1::StreamClipRequest r;
  *r.mutable_motion() = TwoLayers(v1::Motion::EXTRACT);
  r.set_fps(240);
  r.set_speed(10);
  r.set_start_time(2.0);
  r.set_duration(0.15);
  r.set_loop(true);
  const auto frames = Stream(r);
  ASSERT_GE(frames.size(), 30u);
  v1::EvaluateMotionRequest e;
  *e.mutable_motion() = r.motion();
  for (const auto& f : frames) e.add_times(f.time());
  const auto want = client::Client(OptionsFor(*server_)).EvaluateMotion(e);
  ASSERT_EQ(want.root_motion_size(), static_cast<int>(frames.size()));
  double sum[3] = {0, 0, 0};
  for (size_t k = 0; k < frames.size(); ++k) {
    ASSERT_TRUE(frames[k].has_root_delta()) << k;
    ASSERT_EQ(frames[k].root_delta().translations_size(), 3);
    ASSERT_EQ(frames[k].root_delta().rotations_size(), 4);
    for (int i = 0; i < 3; ++i) sum[i] += frames[k].root_delta().translations(i);
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(sum[i], want.root_motion(k).translations(i) - want.root_motion(0).translations(i), 1e-3)
          << k << " " << i;
    for (int i = 0; i < frames[k].pose().translations_size(); ++i)
      ASSERT_EQ(frames[k].pose().translations(i), want.poses(k).translations(i));
  }
  // The first frame's delta is zero; the walk then moves along +Z at its speed,
  // across the loop point at 3 s as anywhere else.
  EXPECT_EQ(frames[0].root_delta().translations(2), 0.f);
  const double elapsed = frames.back().time() - frames.front().time();
  EXPECT_GT(frames.back().time(), 3.0);
  EXPECT_NEAR(sum[2], kDemoWalkSpeed * elapsed, 0.1 * kDemoWalkSpeed * elapsed);
}

// Without loop a motion ends after its first layer's length (3 s at speed 1).
TEST_F(MotionStream, WithoutLoopTheMotionEndsAfterItsFirstLayer) {
  v1::StreamClipRequest r;
  *r.mutable_motion() = TwoLayers(v1::Motion::KEEP);
  r.set_fps(240);
  r.set_speed(20);
  r.set_start_time(2.0);
  const auto frames = Stream(r);
  ASSERT_FALSE(frames.empty());
  EXPECT_LE(frames.back().time(), 3.0 + 1e-9);
  EXPECT_GT(frames.back().time(), 3.0 - 20.0 / 240 - 1e-9);
}

TEST_F(MotionStream, ClipAndMotionAreExclusiveAndErrorsNameTheField) {
  v1::StreamClipRequest both;
  both.set_clip("demo_walk");
  *both.mutable_motion() = TwoLayers(v1::Motion::KEEP);
  grpc::Status st = StatusOf([&] { Stream(both); });
  EXPECT_EQ(st.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(st.error_message().find("clip and motion"), std::string::npos) << st.error_message();
  v1::StreamClipRequest neither;
  st = StatusOf([&] { Stream(neither); });
  EXPECT_EQ(st.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(st.error_message().find("clip or motion"), std::string::npos) << st.error_message();
  v1::StreamClipRequest unknown;
  *unknown.mutable_motion() = TwoLayers(v1::Motion::KEEP);
  unknown.mutable_motion()->mutable_layers(1)->set_clip("no_such_clip");
  st = StatusOf([&] { Stream(unknown); });
  EXPECT_EQ(st.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_NE(st.error_message().find("motion.layers[1]"), std::string::npos) << st.error_message();
}

}  // namespace
}  // namespace armature::testing
