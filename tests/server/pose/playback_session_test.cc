// The playback session's logic without gRPC, over the demo catalog: the
// start's duration or the client's close ends the frames, queued commands
// apply before the next frame, and a refused one names its message.
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
