// Playback: crossfades (three.js crossFadeTo without warping), interrupted
// fades, pause, seek and layer control, against values derived by hand.
//
// Clips on one root joint: A moves the root to (t, 0, 0) at clip time t,
// B to (0, 2t, 0), both 4 s long. Two override layers of weights 1 − a and
// a blend by lerp, so the root is ((1 − a)·tA, a·2·tB, 0).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/playback.h"
#include "../testing/exact_clip.h"

namespace armature {
namespace {

constexpr double kDt = 0.1;  // 10 fps

std::shared_ptr<Skeleton> Root(const char* name = "root") {
  auto s = std::make_shared<Skeleton>();
  s->names = {name};
  s->parents = {-1};
  s->rest.resize(1);
  s->channels.resize(1);
  s->end_sites.resize(1);
  return s;
}

std::shared_ptr<Clip> Line(std::shared_ptr<const Skeleton> skeleton, Eigen::Vector3d per_second) {
  auto c = std::make_shared<Clip>();
  c->skeleton = std::move(skeleton);
  c->joints.resize(1);
  c->duration = 4;
  c->joints[0].translation.times = {0, 4};
  c->joints[0].translation.values = {Eigen::Vector3d::Zero(), 4 * per_second};
  return c;
}

Motion OneClip(std::shared_ptr<const Clip> clip, const char* name) {
  Motion m;
  MotionLayer l;
  l.clip = test_util::ExactClip(std::move(clip));
  l.clip_name = name;
  m.layers.push_back(l);
  return m;
}

class PlaybackTest : public ::testing::Test {
 protected:
  Eigen::Vector3d RootNow() {
    std::vector<Trs> out(1);
    const Status st = playback.Evaluate(ws, out);
    EXPECT_TRUE(st.ok()) << st.message();
    return out[0].translation;
  }
  std::shared_ptr<Skeleton> skeleton = Root();
  Motion a = OneClip(Line(skeleton, {1, 0, 0}), "A");
  Motion b = OneClip(Line(skeleton, {0, 2, 0}), "B");
  Playback playback{skeleton};
  MotionWorkspace ws;
};

TEST_F(PlaybackTest, NothingPlayingIsTheRestPose) {
  skeleton->rest[0].translation = Eigen::Vector3d(1, 2, 3);
  EXPECT_EQ(playback.playing_count(), 0u);
  EXPECT_TRUE(RootNow().isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_TRUE(playback.Describe().layers.empty());
}

TEST_F(PlaybackTest, CrossfadeRampsTheWeightsLinearlyWhileBothRun) {
  ASSERT_TRUE(playback.Play(a, 0, 1).ok());
  for (int i = 0; i < 3; ++i) playback.Advance(kDt);  // A at 0.3 s
  ASSERT_TRUE(playback.Play(b, 0.5, 2).ok());
  // Frame k after the play: a = 0.2k, tA = 0.3 + 0.1k, tB = 0.1k.
  struct Row {
    double weight_a, weight_b, x, y;
  };
  const Row rows[] = {
      {1.0, 0.0, 0.30, 0.00},  // the fade starts: B at its time 0, weight 0
      {0.8, 0.2, 0.32, 0.04},  // 0.8·0.4, 0.2·(2·0.1)
      {0.6, 0.4, 0.30, 0.16},  // 0.6·0.5, 0.4·0.4
      {0.4, 0.6, 0.24, 0.36}, {0.2, 0.8, 0.14, 0.64}, {0.0, 1.0, 0.00, 1.00},  // over: B alone at 0.5 s
      {0.0, 1.0, 0.00, 1.20},
  };
  for (int k = 0; k < 7; ++k) {
    SCOPED_TRACE(k);
    const Row& r = rows[k];
    if (k < 5) {
      ASSERT_EQ(playback.playing_count(), 2u);
      EXPECT_EQ(playback.playing(0).id, 1u);
      EXPECT_NEAR(playback.playing(0).weight, r.weight_a, 1e-12);
      EXPECT_NEAR(playback.playing(0).time, 0.3 + 0.1 * k, 1e-12);
    } else {
      ASSERT_EQ(playback.playing_count(), 1u) << "A stops when its fade-out is complete";
    }
    const PlayingMotion now = playback.playing(playback.playing_count() - 1);
    EXPECT_EQ(now.id, 2u);
    EXPECT_NEAR(now.weight, r.weight_b, 1e-12);
    EXPECT_NEAR(now.time, 0.1 * k, 1e-12);
    const Eigen::Vector3d root = RootNow();
    EXPECT_NEAR(root.x(), r.x, 1e-12);
    EXPECT_NEAR(root.y(), r.y, 1e-12);
    playback.Advance(kDt);
  }
}

TEST_F(PlaybackTest, DescribeIsTheTwoLayerMotionOfTheFade) {
  ASSERT_TRUE(playback.Play(a, 0, 1).ok());
  playback.Advance(1.0);
  ASSERT_TRUE(playback.Play(b, 0.5, 2).ok());
  playback.Advance(0.2);  // a = 0.4, tA = 1.2, tB = 0.2
  const Motion d = playback.Describe();
  ASSERT_EQ(d.layers.size(), 2u);
  EXPECT_NEAR(d.layers[0].weight, 0.6, 1e-12);
  EXPECT_NEAR(d.layers[0].time_offset, 1.2, 1e-12);
  EXPECT_NEAR(d.layers[1].weight, 0.4, 1e-12);
  EXPECT_NEAR(d.layers[1].time_offset, 0.2, 1e-12);
  EXPECT_EQ(d.layers[1].clip_name, "B");
  // Blended at time 0, the description is the pose.
  auto plan = BindMotion(d);
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  MotionWorkspace mws;
  mws.Resize(*plan);
  std::vector<Trs> want(1);
  ASSERT_TRUE((BlendMotionJob{&*plan, 0.0, &mws, want}).Run().ok());
  EXPECT_TRUE(RootNow().isApprox(want[0].translation, 1e-12));
  EXPECT_NEAR(want[0].translation.x(), 0.6 * 1.2, 1e-12);
  EXPECT_NEAR(want[0].translation.y(), 0.4 * 0.4, 1e-12);
}

TEST_F(PlaybackTest, ANewFadeDuringAFadeFadesBothFromWhereTheyAre) {
  Motion c = OneClip(Line(skeleton, {0, 0, 1}), "C");
  ASSERT_TRUE(playback.Play(a, 0, 1).ok());
  ASSERT_TRUE(playback.Play(b, 0.5, 2).ok());
  playback.Advance(0.2);  // A 0.6, B 0.4
  ASSERT_TRUE(playback.Play(c, 1.0, 3).ok());
  playback.Advance(0.5);  // half way: A 0.3, B 0.2, C 0.5
  ASSERT_EQ(playback.playing_count(), 3u);
  EXPECT_NEAR(playback.playing(0).weight, 0.3, 1e-12);
  EXPECT_NEAR(playback.playing(1).weight, 0.2, 1e-12);
  EXPECT_NEAR(playback.playing(2).weight, 0.5, 1e-12);
  EXPECT_NEAR(playback.playing(2).time, 0.5, 1e-12);
  // Lerp accumulation: A then B (share 0.2/0.5), then C (share 0.5/1); weights sum to 1.
  const Eigen::Vector3d root = RootNow();
  EXPECT_NEAR(root.x(), 0.3 * 0.7, 1e-12);      // A at 0.7 s
  EXPECT_NEAR(root.y(), 0.2 * 2 * 0.7, 1e-12);  // B at 0.7 s
  EXPECT_NEAR(root.z(), 0.5 * 0.5, 1e-12);      // C at 0.5 s
  playback.Advance(0.5);
  ASSERT_EQ(playback.playing_count(), 1u);
  EXPECT_EQ(playback.playing(0).id, 3u);
  EXPECT_NEAR(RootNow().z(), 1.0, 1e-12);
}

TEST_F(PlaybackTest, PauseFreezesTimesAndFadesSeekJumps) {
  ASSERT_TRUE(playback.Play(a, 0, 1).ok());
  playback.Advance(kDt);
  playback.Advance(kDt);
  playback.Pause();
  ASSERT_TRUE(playback.Play(b, 0.5, 2).ok());
  for (int i = 0; i < 5; ++i) playback.Advance(kDt);
  EXPECT_TRUE(playback.paused());
  EXPECT_NEAR(playback.playing(0).time, 0.2, 1e-12);
  EXPECT_NEAR(playback.playing(1).weight, 0.0, 1e-12) << "the fade waits too";
  EXPECT_NEAR(RootNow().x(), 0.2, 1e-12);
  ASSERT_TRUE(playback.Seek(1.5).ok());  // the newest: B
  EXPECT_NEAR(playback.playing(1).time, 1.5, 1e-12);
  EXPECT_NEAR(playback.playing(0).time, 0.2, 1e-12);
  playback.Resume();
  playback.Advance(0.25);  // a = 0.5: A at 0.45, B at 1.75
  const Eigen::Vector3d root = RootNow();
  EXPECT_NEAR(root.x(), 0.5 * 0.45, 1e-12);
  EXPECT_NEAR(root.y(), 0.5 * 3.5, 1e-12);
}

TEST_F(PlaybackTest, LayerSpeedKeepsTheTimeContinuousAndWeightFillsWithRest) {
  ASSERT_TRUE(playback.Play(a, 0, 1).ok());
  playback.Advance(0.5);
  ASSERT_TRUE(playback.SetLayerSpeed(0, 2).ok());
  EXPECT_NEAR(RootNow().x(), 0.5, 1e-12) << "no jump where the speed changes";
  playback.Advance(0.1);
  EXPECT_NEAR(RootNow().x(), 0.7, 1e-12);
  ASSERT_TRUE(playback.SetLayerWeight(0, 0.5).ok());
  skeleton->rest[0].translation = Eigen::Vector3d(1, 0, 0);
  EXPECT_NEAR(RootNow().x(), 0.5 * 0.7 + 0.5 * 1, 1e-12);  // the other half is the rest pose
}

TEST_F(PlaybackTest, BadCommandsNameTheFieldAndChangeNothing) {
  auto expect = [](const Status& st, const std::string& part) {
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << st.message();
    EXPECT_NE(st.message().find(part), std::string::npos) << st.message();
  };
  expect(playback.SetLayerWeight(0, 0.5), "nothing is playing");
  expect(playback.Seek(1), "nothing is playing");
  ASSERT_TRUE(playback.Play(a, 0, 1).ok());
  expect(playback.SetLayerWeight(3, 0.5), "layer: 3 is out of range (the motion playing has 1 layer)");
  expect(playback.SetLayerWeight(0, 1.5), "weight: 1.5");
  expect(playback.SetLayerSpeed(0, std::nan("")), "speed");
  expect(playback.Seek(-1), "time: -1");
  expect(playback.Play(b, -0.5, 2), "crossfade: -0.5");
  Motion other = OneClip(Line(Root("pelvis"), {1, 1, 1}), "Other");
  expect(playback.Play(other, 0.5, 3), "joint 0 is 'pelvis', the session's is 'root'");
  Motion empty;
  expect(playback.Play(empty, 0.5, 4), "layers");
  ASSERT_EQ(playback.playing_count(), 1u);
  EXPECT_EQ(playback.playing(0).id, 1u);
  EXPECT_NEAR(playback.playing(0).weight, 1.0, 0);
}

TEST_F(PlaybackTest, AtMostEightMotionsPlayTheOldestGoes) {
  for (uint64_t id = 1; id <= 9; ++id) ASSERT_TRUE(playback.Play(a, 1.0, id).ok());
  ASSERT_EQ(playback.playing_count(), Playback::kMaxMotions);
  EXPECT_EQ(playback.playing(0).id, 2u);
  EXPECT_EQ(playback.playing(7).id, 9u);
}

}  // namespace
}  // namespace armature
