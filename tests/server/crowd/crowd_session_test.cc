// The crowd session's logic without gRPC, over the demo catalog: frames carry
// the characters' poses (decoded, the clip's at each clip time within the
// encoding's bound), a layout once per clip, and refused commands as errors
// naming the character while the session keeps running.
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "server/crowd/crowd_session.h"

namespace armature::server {
namespace {

using test_util::DemoCatalog;

v1::CrowdCommand Start(double fps) {
  v1::CrowdCommand c;
  c.mutable_start()->set_fps(fps);
  return c;
}

v1::CrowdCommand Add(uint32_t id, const std::string& clip, double offset = 0) {
  v1::CrowdCommand c;
  c.mutable_add()->set_id(id);
  c.mutable_add()->set_clip(clip);
  c.mutable_add()->set_time_offset(offset);
  return c;
}

class CrowdSessionLogic : public ::testing::Test {
 protected:
  std::shared_ptr<const Catalog> catalog_ = DemoCatalog();
  Limits limits_ = [] {
    Limits l;
    l.max_crowd_characters = 3;
    return l;
  }();
  std::shared_ptr<CrowdTotals> totals_ = std::make_shared<CrowdTotals>(100);
  CrowdSession session_{[this] { return catalog_; }, limits_, totals_};
  v1::CrowdFrame frame_;
};

TEST_F(CrowdSessionLogic, FramesCarryEachCharactersPoseAtItsClipTime) {
  ASSERT_TRUE(session_.Start({}, Start(10)).ok());
  session_.Queue(Add(1, "demo_walk", 0.25));
  session_.Queue(Add(2, "demo_walk", 0.5));
  ASSERT_TRUE(session_.ApplyQueued().ok());
  ASSERT_TRUE(*session_.NextFrame(false, &frame_));
  ASSERT_EQ(frame_.ids_size(), 2);
  ASSERT_EQ(frame_.new_layouts_size(), 1);
  const v1::CrowdLayout layout = frame_.new_layouts(0);  // a copy: the next frame clears frame_
  EXPECT_EQ(layout.clip(), "demo_walk");
  EXPECT_EQ(frame_.poses().size(), 2 * layout.pose_bytes());
  EXPECT_NEAR(layout.max_rotation_error(), 1.495e-4, 1e-6);
  EXPECT_EQ(frame_.errors_size(), 0);
  EXPECT_EQ(totals_->characters(), 2);
  // The second frame sends no layout again.
  ASSERT_TRUE(*session_.NextFrame(false, &frame_));
  EXPECT_EQ(frame_.new_layouts_size(), 0);
  EXPECT_EQ(frame_.tick(), 1u);
  EXPECT_DOUBLE_EQ(frame_.time(), 0.1);
  // Decoded against the clip's runtime form, the one the session samples.
  auto clip = catalog_->FindClip("demo_walk");
  ASSERT_TRUE(clip.ok());
  const std::shared_ptr<const CompressedClip> runtime = clip->part->runtime;
  ASSERT_NE(runtime, nullptr);
  auto engine_layout = LayoutOfClip(*runtime);
  ASSERT_TRUE(engine_layout.ok());
  std::vector<Trs> decoded(engine_layout->joints), expected(engine_layout->joints);
  for (int i = 0; i < frame_.ids_size(); ++i) {
    const double offset = frame_.ids(i) == 1 ? 0.25 : 0.5;
    EXPECT_NEAR(frame_.clip_times(i), WrapTime(offset + 0.1, runtime->duration, WrapMode::kLoop), 1.0 / 240);
    std::span<const uint8_t> bytes(reinterpret_cast<const uint8_t*>(frame_.poses().data()) + i * layout.pose_bytes(),
                                   layout.pose_bytes());
    ASSERT_TRUE(DecodePose(*engine_layout, bytes, decoded).ok());
    ASSERT_TRUE((ClipSamplingJob{runtime.get(), frame_.clip_times(i), WrapMode::kLoop, nullptr, expected, std::nullopt}
                     .Run()
                     .ok()));
    for (size_t j = 0; j < decoded.size(); ++j)
      EXPECT_LE(2 * std::acos(std::min(1.0, std::abs(decoded[j].rotation.dot(expected[j].rotation.normalized())))),
                layout.max_rotation_error() + 1e-6);
  }
}

TEST_F(CrowdSessionLogic, RefusedCommandsNameTheCharacterAndTheSessionRunsOn) {
  ASSERT_TRUE(session_.Start({}, Start(30)).ok());
  session_.Queue(Add(1, "demo_walk"));
  session_.Queue(Add(1, "demo_walk"));     // duplicate
  session_.Queue(Add(2, "no_such_clip"));  // unknown clip
  v1::CrowdCommand nan = Add(3, "demo_walk");
  nan.mutable_add()->set_speed(std::numeric_limits<double>::quiet_NaN());
  session_.Queue(nan);
  v1::CrowdCommand inf_root = Add(4, "demo_walk");
  inf_root.mutable_add()->mutable_root()->add_translation(std::numeric_limits<double>::infinity());
  inf_root.mutable_add()->mutable_root()->add_translation(0);
  inf_root.mutable_add()->mutable_root()->add_translation(0);
  session_.Queue(inf_root);
  v1::CrowdCommand both = Add(5, "demo_walk");  // a skeleton and a character
  both.mutable_add()->set_skeleton("demo_walk");
  both.mutable_add()->set_character("demo_walk");
  session_.Queue(both);
  v1::CrowdCommand remove;
  remove.set_remove(9);  // unknown
  session_.Queue(remove);
  session_.Queue(Add(6, "demo_walk"));
  session_.Queue(Add(7, "demo_walk"));
  session_.Queue(Add(8, "demo_walk"));  // the fourth: over --max-crowd-characters (3)
  ASSERT_TRUE(session_.ApplyQueued().ok());
  ASSERT_TRUE(*session_.NextFrame(false, &frame_));
  EXPECT_EQ(frame_.stats().characters(), 3u);
  ASSERT_EQ(frame_.errors_size(), 7);
  const std::vector<std::pair<uint32_t, int>> expected = {{1, 6}, {2, 5}, {3, 3}, {4, 3}, {5, 3}, {9, 5}, {8, 8}};
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(frame_.errors(i).id(), expected[i].first) << frame_.errors(i).error();
    EXPECT_EQ(frame_.errors(i).code(), expected[i].second) << frame_.errors(i).error();
    EXPECT_EQ(frame_.errors(i).error().rfind("character " + std::to_string(expected[i].first) + ": ", 0), 0u)
        << frame_.errors(i).error();
  }
  EXPECT_NE(frame_.errors(6).error().find("--max-crowd-characters"), std::string::npos);
  ASSERT_TRUE(*session_.NextFrame(false, &frame_));
  EXPECT_EQ(frame_.errors_size(), 0);
}

TEST_F(CrowdSessionLogic, ABadStartIsRefusedNamingItsField) {
  v1::CrowdCommand start = Start(30);
  start.mutable_start()->set_budget_ms(1e6);
  Status st = session_.Start({}, start);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("start.budget_ms"), std::string::npos) << st.message();
  EXPECT_FALSE(session_.Start({}, Add(1, "demo_walk")).ok());
}

TEST_F(CrowdSessionLogic, TheServerWideCapAndRemovalsAreCounted) {
  auto small = std::make_shared<CrowdTotals>(1);
  {
    CrowdSession a([this] { return catalog_; }, limits_, small);
    ASSERT_TRUE(a.Start({}, Start(30)).ok());
    a.Queue(Add(1, "demo_walk"));
    a.Queue(Add(2, "demo_walk"));
    ASSERT_TRUE(a.ApplyQueued().ok());
    ASSERT_TRUE(*a.NextFrame(false, &frame_));
    ASSERT_EQ(frame_.errors_size(), 1);
    EXPECT_NE(frame_.errors(0).error().find("--max-crowd-characters-total"), std::string::npos);
    EXPECT_EQ(small->characters(), 1);
  }
  EXPECT_EQ(small->characters(), 0);  // the session's end gives them back
}

}  // namespace
}  // namespace armature::server
