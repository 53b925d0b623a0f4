// PlaybackSession's commands and frames without gRPC, over the demo catalog:
// a frame inside a crossfade is EvaluateMotion's two-layer blend; commands
// name their field when refused.
#include <cmath>

#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "server/pose/playback_commands.h"
#include "server/pose/pose_handlers.h"

namespace armature::server {
namespace {

using test_util::DemoCatalog;

class PlaybackCommands : public ::testing::Test {
 protected:
  void SetUp() override {
    v1::PlaybackStart start;
    start.set_skeleton("demo_walk");
    start.set_fps(10);
    start.mutable_play()->set_clip("demo_walk");
    auto s = StartPlayback(*catalog, limits, start, playback, names);
    ASSERT_TRUE(s.ok()) << s.status().message();
    setup = std::move(*s);
  }
  v1::PlaybackFrame Frame(uint64_t index) {
    v1::PlaybackFrame f;
    const Status st = FillPlaybackFrame(setup, *playback, names, index, motion_ws, pose_ws, f);
    EXPECT_TRUE(st.ok()) << st.message();
    return f;
  }
  Status Apply(const v1::PlaybackCommand& c, uint64_t id) {
    return ApplyPlaybackCommand(*catalog, limits, c, id, *playback, names);
  }
  std::shared_ptr<const Catalog> catalog = DemoCatalog();
  const Limits limits;
  PlaybackSetup setup;
  std::unique_ptr<Playback> playback;
  std::map<uint64_t, std::string> names;
  MotionWorkspace motion_ws;
  PoseWorkspace pose_ws;
};

TEST_F(PlaybackCommands, AFrameInsideACrossfadeIsTheTwoLayerMotion) {
  EXPECT_EQ(setup.fps, 10);
  for (int i = 0; i < 4; ++i) playback->Advance(0.1);  // the walk at 0.4 s
  v1::PlaybackCommand play;
  play.mutable_play()->set_clip("demo_walk");
  play.mutable_play()->set_crossfade(0.5);
  ASSERT_TRUE(Apply(play, 1).ok());
  for (int i = 0; i < 2; ++i) playback->Advance(0.1);  // a = 0.4
  const v1::PlaybackFrame f = Frame(6);
  EXPECT_DOUBLE_EQ(f.time(), 0.6);
  ASSERT_EQ(f.motions_size(), 2);
  EXPECT_EQ(f.motions(0).name(), "demo_walk");
  EXPECT_NEAR(f.motions(0).weight(), 0.6, 1e-12);
  EXPECT_NEAR(f.motions(0).time(), 0.6, 1e-12);
  EXPECT_EQ(f.motions(1).id(), 1u);
  EXPECT_NEAR(f.motions(1).weight(), 0.4, 1e-12);
  EXPECT_NEAR(f.motions(1).time(), 0.2, 1e-12);
  EXPECT_TRUE(f.skeleton().empty()) << "only the first frame names the skeleton";

  v1::EvaluateMotionRequest want;
  for (auto [weight, time] : {std::pair{0.6, 0.6}, std::pair{0.4, 0.2}}) {
    v1::MotionLayer* l = want.mutable_motion()->add_layers();
    l->set_clip("demo_walk");
    l->set_weight(weight);
    l->set_time_offset(time);
  }
  want.add_times(0);
  v1::EvaluateMotionResponse r;
  ASSERT_TRUE(EvaluateMotion(*catalog, limits, want, &r).ok());
  ASSERT_EQ(r.poses(0).translations_size(), f.pose().translations_size());
  for (int i = 0; i < f.pose().translations_size(); ++i)
    EXPECT_NEAR(f.pose().translations(i), r.poses(0).translations(i), 1e-4) << i;
  for (int i = 0; i < f.pose().rotations_size(); ++i)
    EXPECT_NEAR(f.pose().rotations(i), r.poses(0).rotations(i), 1e-6) << i;
  EXPECT_EQ(Frame(0).skeleton(), "demo_walk");
}

TEST_F(PlaybackCommands, RefusedCommandsNameTheirField) {
  auto expect = [&](const v1::PlaybackCommand& c, StatusCode code, const std::string& part) {
    const Status st = Apply(c, 1);
    EXPECT_EQ(st.code(), code) << st.message();
    EXPECT_NE(st.message().find(part), std::string::npos) << st.message();
  };
  expect(v1::PlaybackCommand(), StatusCode::kInvalidArgument, "command: empty");
  v1::PlaybackCommand c;
  c.mutable_set_layer();
  expect(c, StatusCode::kInvalidArgument, "set_layer: give a weight, a speed or both");
  c.mutable_set_layer()->set_layer(-1);
  c.mutable_set_layer()->set_speed(2);
  expect(c, StatusCode::kInvalidArgument, "set_layer.layer: -1 is negative");
  c.mutable_set_layer()->set_layer(0);
  c.mutable_set_layer()->set_weight(-0.5);
  expect(c, StatusCode::kInvalidArgument, "set_layer.weight: -0.5");
  v1::PlaybackCommand play;
  play.mutable_play();
  expect(play, StatusCode::kInvalidArgument, "play: give a clip or a motion");
  play.mutable_play()->set_clip("nope");
  expect(play, StatusCode::kNotFound, "play.clip: ");
  play.mutable_play()->set_clip("demo_walk");
  play.mutable_play()->set_crossfade(std::nan(""));
  expect(play, StatusCode::kInvalidArgument, "play.crossfade");
  // Nothing refused changed the playback: the walk alone, speed 1, weight 1.
  ASSERT_EQ(playback->playing_count(), 1u);
  EXPECT_EQ(playback->Describe().layers[0].weight, 1);
}

}  // namespace
}  // namespace armature::server
