// The playback session's logic without gRPC, over the demo catalog: the
// start's duration or the client's close ends the frames, queued commands
// apply before the next frame (or, with a later `at`, before the first frame
// at or after it), and a refused one names its message.
#include <limits>

#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "server/pose/playback_session.h"

namespace armature::server {
namespace {

using test_util::DemoCatalog;

v1::PlaybackCommand StartCommand(double fps, double duration) {
  v1::PlaybackCommand c;
  c.mutable_start()->set_skeleton("demo_walk");
  c.mutable_start()->set_fps(fps);
  c.mutable_start()->set_duration(duration);
  c.mutable_start()->mutable_play()->set_clip("demo_walk");
  return c;
}

class PlaybackSessionLogic : public ::testing::Test {
 protected:
  // The frames until the session is over (at most `most`).
  int FramesUntilOver(bool closed, int most) {
    for (int n = 0; n < most; ++n) {
      auto more = session_.NextFrame(closed, &frame_);
      EXPECT_TRUE(more.ok()) << more.status().message();
      if (!more.ok() || !*more) return n;
      EXPECT_EQ(frame_.index(), static_cast<uint64_t>(n));
    }
    return most;
  }
  std::shared_ptr<const Catalog> catalog_ = DemoCatalog();
  const Limits limits_;
  PlaybackSession session_{[this] { return catalog_; }, limits_};
  v1::PlaybackFrame frame_;
};

TEST_F(PlaybackSessionLogic, TheDurationEndsTheFrames) {
  ASSERT_TRUE(session_.Start({}, StartCommand(10, 0.3)).ok());
  EXPECT_EQ(session_.fps(), 10);
  EXPECT_EQ(FramesUntilOver(false, 10), 3);
  EXPECT_EQ(session_.frames(), 3u);
}

TEST_F(PlaybackSessionLogic, WithoutADurationTheClientsCloseEndsThem) {
  ASSERT_TRUE(session_.Start({}, StartCommand(10, 0)).ok());
  EXPECT_EQ(FramesUntilOver(false, 5), 5);
  EXPECT_EQ(FramesUntilOver(true, 5), 0);
}

TEST_F(PlaybackSessionLogic, QueuedCommandsApplyInOrderAndARefusalNamesItsMessage) {
  ASSERT_TRUE(session_.Start({}, StartCommand(10, 0)).ok());
  v1::PlaybackCommand play;
  play.mutable_play()->set_clip("demo_walk");
  session_.Queue(play);
  EXPECT_EQ(session_.queued(), 1u);
  ASSERT_TRUE(session_.ApplyQueued().ok());
  EXPECT_EQ(session_.queued(), 0u);
  ASSERT_TRUE(*session_.NextFrame(false, &frame_));
  EXPECT_EQ(frame_.motions(frame_.motions_size() - 1).id(), 1u);

  v1::PlaybackCommand bad;
  bad.mutable_play()->set_clip("nope");
  session_.Queue(bad);
  const Status st = session_.ApplyQueued();
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_EQ(st.message().rfind("message 2: play.clip: ", 0), 0u) << st.message();
  EXPECT_EQ(session_.queued(), 0u);
}

v1::PlaybackCommand PlayAt(double at, double crossfade = 0.2) {
  v1::PlaybackCommand c;
  c.mutable_play()->set_clip("demo_walk");
  c.mutable_play()->set_crossfade(crossfade);
  c.set_at(at);
  return c;
}

TEST_F(PlaybackSessionLogic, APlayAtHalfASecondStartsItsCrossfadeAtFrame15) {
  ASSERT_TRUE(session_.Start({}, StartCommand(30, 1)).ok());
  session_.Queue(PlayAt(0.5));  // sent before frame 0, as `armature play --then … --at 0.5` does
  for (int k = 0; k <= 15; ++k) {
    ASSERT_TRUE(session_.ApplyQueued().ok()) << k;
    ASSERT_TRUE(*session_.NextFrame(false, &frame_)) << k;
    if (k < 15) {
      ASSERT_EQ(frame_.motions_size(), 1) << "frame " << k << " already shows the next play";
      EXPECT_EQ(session_.waiting(), 1u) << k;
    }
  }
  EXPECT_DOUBLE_EQ(frame_.time(), 0.5);
  ASSERT_EQ(frame_.motions_size(), 2);
  EXPECT_EQ(frame_.motions(1).id(), 1u);
  EXPECT_EQ(frame_.motions(1).weight(), 0);  // its crossfade starts here
  EXPECT_EQ(frame_.motions(1).time(), 0);
  EXPECT_EQ(frame_.motions(0).weight(), 1);
  EXPECT_EQ(session_.waiting(), 0u);
}

TEST_F(PlaybackSessionLogic, HeldCommandsApplyByTheirTimeThenInTheOrderSent) {
  ASSERT_TRUE(session_.Start({}, StartCommand(10, 0)).ok());
  ASSERT_TRUE(*session_.NextFrame(false, &frame_));  // frame 0; the next is at 0.1
  session_.Queue(PlayAt(0.2, 0));                    // message 1
  session_.Queue(PlayAt(0.1, 0));                    // message 2
  session_.Queue(PlayAt(0.05, 0));                   // message 3: already past, so now
  ASSERT_TRUE(session_.ApplyQueued().ok());
  ASSERT_TRUE(*session_.NextFrame(false, &frame_));
  EXPECT_EQ(frame_.motions(frame_.motions_size() - 1).id(), 3u);  // 2 (due at 0.1) before 3 (sent now)
  EXPECT_EQ(session_.waiting(), 1u);
  ASSERT_TRUE(session_.ApplyQueued().ok());
  ASSERT_TRUE(*session_.NextFrame(false, &frame_));
  EXPECT_DOUBLE_EQ(frame_.time(), 0.2);
  EXPECT_EQ(frame_.motions(frame_.motions_size() - 1).id(), 1u);
}

TEST_F(PlaybackSessionLogic, AnAtMustBeFiniteAndNotNegative) {
  for (double at : {-0.5, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    PlaybackSession session{[this] { return catalog_; }, limits_};
    ASSERT_TRUE(session.Start({}, StartCommand(10, 0)).ok());
    session.Queue(PlayAt(at));
    const Status st = session.ApplyQueued();
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << at;
    EXPECT_EQ(st.message().rfind("message 1: at: ", 0), 0u) << st.message();
  }
  v1::PlaybackCommand start = StartCommand(10, 0);
  start.set_at(1);
  const Status st = session_.Start({}, start);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message().rfind("at: the start applies at once", 0), 0u) << st.message();
}

TEST_F(PlaybackSessionLogic, AtMost64CommandsWaitForTheirTime) {
  ASSERT_TRUE(session_.Start({}, StartCommand(10, 0)).ok());
  for (size_t n = 0; n < PlaybackSession::kMaxWaiting; ++n) session_.Queue(PlayAt(5));
  session_.Queue(PlayAt(0));  // due now: does not count
  ASSERT_TRUE(session_.ApplyQueued().ok());
  EXPECT_EQ(session_.waiting(), PlaybackSession::kMaxWaiting);
  session_.Queue(PlayAt(5));
  const Status st = session_.ApplyQueued();
  EXPECT_EQ(st.code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(st.message(), "message 66: at: more than 64 commands would wait for their time");
}

TEST_F(PlaybackSessionLogic, TheFirstMessageMustStartIt) {
  v1::PlaybackCommand play;
  play.mutable_play()->set_clip("demo_walk");
  const Status st = session_.Start({}, play);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message().rfind("start: required in the first message", 0), 0u) << st.message();
  EXPECT_EQ(session_.Start({}, StartCommand(0, 0)).code(), StatusCode::kOk);  // fps 0: the default 30
  EXPECT_EQ(session_.fps(), 30);
}

}  // namespace
}  // namespace armature::server
