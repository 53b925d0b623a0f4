#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/io/bvh/bvh.h"
#include "../testing/bvh_reference.h"
#include "../testing/test_files.h"

namespace armature {
namespace {

using testing::EnginePositionsAt;
using testing::EngineWorldPositions;
using testing::MakeTestBvh;
using testing::MaxDistance;
using testing::ParseExpectOk;
using testing::RefBvh;
using testing::RefJoint;

class BvhChannelOrder : public ::testing::TestWithParam<std::string> {};

TEST_P(BvhChannelOrder, ParsedPosesMatchIndependentMatrixFk) {
  const RefBvh ref = MakeTestBvh(GetParam());
  const BvhData d = ParseExpectOk(testing::WriteRefBvh(ref));
  ASSERT_TRUE(d.skeleton && d.clip);
  ASSERT_EQ(d.skeleton->size(), ref.joints.size());
  for (size_t j = 0; j < ref.joints.size(); ++j) {
    EXPECT_EQ(d.skeleton->names[j], ref.joints[j].name);
    EXPECT_EQ(d.skeleton->parents[j], ref.joints[j].parent);
    EXPECT_EQ(d.skeleton->rest[j].translation, ref.joints[j].offset);
    EXPECT_EQ(d.skeleton->end_sites[j], ref.joints[j].end_site);
    ASSERT_EQ(d.skeleton->channels[j].size(), ref.joints[j].channels.size());
    for (size_t c = 0; c < ref.joints[j].channels.size(); ++c)
      EXPECT_EQ(ChannelName(d.skeleton->channels[j][c]), ref.joints[j].channels[c]);
  }
  for (size_t f = 0; f < ref.frames.size(); ++f) {
    const auto expected = testing::RefWorldPositions(ref, testing::RefLocals(ref, f));
    EXPECT_LT(MaxDistance(EnginePositionsAt(d, f * ref.frame_time), expected), 1e-9) << "frame " << f;
  }
  for (double x : {0.3, 4.5, 10.99}) {
    const double t = x * ref.frame_time;
    EXPECT_LT(MaxDistance(EnginePositionsAt(d, t), testing::RefWorldPositionsAt(ref, t)), 1e-9) << "time " << t;
  }
}

TEST_P(BvhChannelOrder, WriteThenReadGivesTheSamePoses) {
  const RefBvh ref = MakeTestBvh(GetParam());
  const BvhData d = ParseExpectOk(testing::WriteRefBvh(ref));
  ASSERT_TRUE(d.clip);
  const std::string written = WriteBvh(*d.clip);
  const BvhData back = ParseExpectOk(written);
  ASSERT_TRUE(back.clip);
  EXPECT_EQ(back.skeleton->names, d.skeleton->names);
  EXPECT_EQ(back.skeleton->channels, d.skeleton->channels);
  EXPECT_EQ(back.skeleton->end_sites, d.skeleton->end_sites);
  EXPECT_EQ(back.clip->frame_count, d.clip->frame_count);
  EXPECT_DOUBLE_EQ(back.clip->frame_time, d.clip->frame_time);
  for (size_t f = 0; f < ref.frames.size(); ++f) {
    const double t = f * ref.frame_time;
    EXPECT_LT(MaxDistance(EnginePositionsAt(back, t), EnginePositionsAt(d, t)), 1e-4) << "frame " << f;
  }
}

INSTANTIATE_TEST_SUITE_P(AllTaitBryanAndProperEuler, BvhChannelOrder,
                         ::testing::Values("XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX", "ZXZ", "YXY"));

TEST(Bvh, ClipHasRotationAndTranslationTracksOnlyForJointsWithThoseChannels) {
  const RefBvh ref = MakeTestBvh("ZXY", 5);
  const BvhData d = ParseExpectOk(testing::WriteRefBvh(ref));
  ASSERT_TRUE(d.clip);
  const Clip& c = *d.clip;
  EXPECT_TRUE(c.Validate().ok());
  EXPECT_EQ(c.frame_count, 5u);
  EXPECT_DOUBLE_EQ(c.frame_time, 0.05);
  EXPECT_DOUBLE_EQ(c.duration, 4 * 0.05);
  EXPECT_EQ(c.default_interpolation, Interpolation::kLinear);
  ASSERT_EQ(c.joints.size(), ref.joints.size());
  for (size_t j = 0; j < ref.joints.size(); ++j) {
    const bool has_position =
        std::any_of(ref.joints[j].channels.begin(), ref.joints[j].channels.end(),
                    [](const std::string& ch) { return ch.find("position") != std::string::npos; });
    const bool has_rotation =
        std::any_of(ref.joints[j].channels.begin(), ref.joints[j].channels.end(),
                    [](const std::string& ch) { return ch.find("rotation") != std::string::npos; });
    EXPECT_EQ(c.joints[j].rotation.times.size(), has_rotation ? 5u : 0u) << ref.joints[j].name;
    EXPECT_EQ(c.joints[j].translation.times.size(), has_position ? 5u : 0u) << ref.joints[j].name;
    EXPECT_TRUE(c.joints[j].scale.empty());
    if (!has_rotation) continue;
    EXPECT_EQ(c.joints[j].rotation.interpolation, Interpolation::kLinear);
    EXPECT_DOUBLE_EQ(c.joints[j].rotation.times[3], 3 * 0.05);
  }
  // Root translation = OFFSET + position channels (Yposition Xposition Zposition).
  const Eigen::Vector3d t0 = c.joints[0].translation.values[0];
  EXPECT_NEAR(t0.x(), 3.5 + ref.frames[0][1], 1e-12);
  EXPECT_NEAR(t0.y(), -2.0 + ref.frames[0][0], 1e-12);
  EXPECT_NEAR(t0.z(), 5.25 + ref.frames[0][2], 1e-12);
}

TEST(Bvh, ToleratesCaseCrlfAndBracesOnTheNameLine) {
  const RefBvh ref = MakeTestBvh("XZY", 4);
  const std::string text = testing::WriteRefBvh(ref);
  std::string odd;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n')
      odd += "\r\n";
    else
      odd += text[i];
  }
  for (const std::string& from : {"position", "rotation", "OFFSET", "CHANNELS", "End Site", "Frame Time", "JOINT"}) {
    std::string to = from;
    for (char& ch : to)
      ch = static_cast<char>(from == "position" || from == "rotation" ? std::toupper(ch) : std::tolower(ch));
    for (size_t p = odd.find(from); p != std::string::npos; p = odd.find(from, p + to.size()))
      odd.replace(p, from.size(), to);
  }
  // "ROOT Hips {" on one line.
  odd.replace(odd.find("ROOT Hips\r\n{"), 12, "ROOT Hips {");
  ASSERT_NE(odd.find("XPOSITION"), std::string::npos);
  const BvhData a = ParseExpectOk(text), b = ParseExpectOk(odd);
  ASSERT_TRUE(a.clip && b.clip);
  EXPECT_EQ(a.skeleton->names, b.skeleton->names);
  EXPECT_EQ(a.skeleton->channels, b.skeleton->channels);
  for (size_t f = 0; f < 4; ++f)
    EXPECT_EQ(MaxDistance(EnginePositionsAt(a, f * 0.05), EnginePositionsAt(b, f * 0.05)), 0.0);
}

TEST(Bvh, ZeroFramesIsASkeletonWithEmptyTracks) {
  const std::string text =
      "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n}\n"
      "MOTION\nFrames: 0\nFrame Time: 0.1\n";
  const BvhData d = ParseExpectOk(text);
  ASSERT_TRUE(d.clip);
  EXPECT_EQ(d.clip->frame_count, 0u);
  EXPECT_EQ(d.clip->duration, 0.0);
  EXPECT_TRUE(d.clip->joints[0].rotation.empty());
}

// A two-joint file; the line numbers are those in the comments.
const char* kSmall =
    "HIERARCHY\n"                                                                 // 1
    "ROOT Hips\n"                                                                 // 2
    "{\n"                                                                         // 3
    "  OFFSET 0 0 0\n"                                                            // 4
    "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"  // 5
    "  JOINT Chest\n"                                                             // 6
    "  {\n"                                                                       // 7
    "    OFFSET 0 5 0\n"                                                          // 8
    "    CHANNELS 3 Zrotation Xrotation Yrotation\n"                              // 9
    "    End Site\n"                                                              // 10
    "    {\n"                                                                     // 11
    "      OFFSET 0 3 0\n"                                                        // 12
    "    }\n"                                                                     // 13
    "  }\n"                                                                       // 14
    "}\n"                                                                         // 15
    "MOTION\n"                                                                    // 16
    "Frames: 2\n"                                                                 // 17
    "Frame Time: 0.1\n"                                                           // 18
    "0 1 2 3 4 5 6 7 8\n"                                                         // 19
    "1 2 3 4 5 6 7 8 9\n";                                                        // 20

std::string Replace(std::string s, const std::string& from, const std::string& to) {
  const size_t p = s.find(from);
  EXPECT_NE(p, std::string::npos) << from;
  if (p != std::string::npos) s.replace(p, from.size(), to);
  return s;
}

std::string Lines(int first, int last) {  // lines first..last of kSmall
  std::string out, s = kSmall;
  int line = 1;
  for (size_t i = 0; i < s.size(); ++i) {
    if (line >= first && line <= last) out += s[i];
    if (s[i] == '\n') ++line;
  }
  return out;
}

void ExpectError(const std::string& text, const std::string& fragment) {
  const StatusOr<BvhData> d = ParseBvh(text);
  ASSERT_FALSE(d.ok()) << "expected an error containing: " << fragment;
  EXPECT_EQ(d.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(d.status().message().find(fragment), std::string::npos)
      << "message: " << d.status().message() << "\nexpected to contain: " << fragment;
}

TEST(BvhErrors, SmallFileParses) {
  const BvhData d = ParseExpectOk(kSmall);
  ASSERT_TRUE(d.skeleton);
  EXPECT_EQ(d.skeleton->names, (std::vector<std::string>{"Hips", "Chest"}));
  EXPECT_EQ(d.skeleton->end_sites[1], Eigen::Vector3d(0, 3, 0));
}

TEST(BvhErrors, HierarchyMistakesNameTheLine) {
  ExpectError("", "line 1: expected HIERARCHY, found end of file");
  ExpectError(Replace(kSmall, "HIERARCHY", "HIERARCHIE"), "line 1: expected HIERARCHY, found 'HIERARCHIE'");
  ExpectError(Replace(kSmall, "ROOT Hips", "BONE Hips"), "line 2: expected ROOT, found 'BONE'");
  ExpectError(Replace(kSmall, "    OFFSET 0 5 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n",
                      "    CHANNELS 3 Zrotation Xrotation Yrotation\n    OFFSET 0 5 0\n"),
              "line 8: expected OFFSET, found 'CHANNELS'");
  ExpectError(Replace(kSmall, "OFFSET 0 5 0", "OFFSET 0 five 0"), "line 8: expected a number for OFFSET, found 'five'");
  ExpectError(Replace(kSmall, "OFFSET 0 5 0", "OFFSET 0 nan 0"), "line 8: OFFSET value 'nan' is not finite");
  ExpectError(Replace(kSmall, "CHANNELS 3 Zrotation", "CHANNELS 4 Zrotation"),
              "line 9: CHANNELS declares 4 channels but lists 3 (next is 'End' on line 10)");
  ExpectError(Replace(kSmall, "CHANNELS 3 Zrotation", "CHANNELS 3 Wrotation"), "line 9: unknown channel 'Wrotation'");
  ExpectError(Replace(kSmall, "CHANNELS 3", "CHANNELS three"), "line 9: channel count 'three' is not a whole number");
  ExpectError(Replace(kSmall, "CHANNELS 3", "CHANNELS -3"), "line 9: channel count '-3'");
  ExpectError(Replace(kSmall, "Zposition Zrotation", "Xposition Zrotation"),
              "line 5: channel Xposition is listed twice");
  ExpectError(Replace(kSmall, "JOINT Chest", "JOINT Hips"), "line 6: duplicate joint name 'Hips' (first on line 2)");
  ExpectError(Replace(kSmall, "JOINT Chest", "JOINT"), "line 6: joint has no name");
  ExpectError(Replace(kSmall, "  JOINT Chest\n  {", "  JOINT Chest\n  ("), "line 7: expected {, found '('");
  ExpectError(Replace(kSmall, "End Site", "End Sight"), "line 10: expected 'End Site', found 'End Sight'");
  ExpectError(Replace(kSmall, "End Site", "Ending Site"),
              "line 10: expected JOINT, End Site or '}' in joint 'Chest', found 'Ending'");
}

TEST(BvhErrors, TruncatedFilesNameWhereTheyEnd) {
  ExpectError(Lines(1, 11), "line 12: expected OFFSET, found end of file");
  ExpectError(Lines(1, 13), "line 14: file ends inside joint 'Chest' (missing '}')");
  ExpectError(Lines(1, 15), "line 16: expected ROOT or MOTION, found end of file");
  ExpectError(Lines(1, 16), "expected 'Frames: <count>', found end of file");
  ExpectError(Lines(1, 17), "expected 'Frame Time: <seconds>', found end of file");
  ExpectError(Lines(1, 19), "file ends after 1 of the 2 frames that 'Frames:' on line 17 declares");
}

TEST(BvhErrors, MotionMistakesNameTheLine) {
  ExpectError(Replace(kSmall, "Frames: 2", "Frames 2"), "line 17: expected 'Frames: <count>', found 'Frames 2'");
  ExpectError(Replace(kSmall, "Frames: 2", "Frames: two"), "line 17: frame count 'two' is not a whole number");
  ExpectError(Replace(kSmall, "Frames: 2", "Frames: -2"), "line 17: frame count '-2'");
  ExpectError(Replace(kSmall, "Frames: 2", "Frames: 3"), "file ends after 2 of the 3 frames that 'Frames:' on line 17");
  ExpectError(Replace(kSmall, "Frame Time: 0.1", "Frame Time: 0"), "line 18: frame time '0' is not a positive number");
  ExpectError(Replace(kSmall, "Frame Time: 0.1", "Frame Time: -0.1"), "line 18: frame time '-0.1'");
  ExpectError(Replace(kSmall, "Frame Time: 0.1", "Frame Time: nan"), "line 18: frame time 'nan'");
  ExpectError(Replace(kSmall, "Frame Time: 0.1", "Frame Time: fast"), "line 18: frame time 'fast'");
  ExpectError(Replace(kSmall, "1 2 3 4 5 6 7 8 9", "1 2 3 4 5 6 7 8"), "line 20: frame 1 has 8 values, expected 9");
  ExpectError(Replace(kSmall, "1 2 3 4 5 6 7 8 9", "1 2 3 4 5 6 7 8 9 10"),
              "line 20: frame 1 has 10 values, expected 9");
  ExpectError(Replace(kSmall, "0 1 2 3 4", "0 1 2 nan 4"), "line 19: frame 0 value 4 'nan' is not finite");
  ExpectError(Replace(kSmall, "0 1 2 3 4", "0 1 2 -inf 4"), "line 19: frame 0 value 4 '-inf' is not finite");
  ExpectError(Replace(kSmall, "0 1 2 3 4", "0 1 2 1e999 4"), "line 19: frame 0 value 4 '1e999' is not a number");
  ExpectError(Replace(kSmall, "0 1 2 3 4", "0 1 2 3,5 4"), "line 19: frame 0 value 4 '3,5' is not a number");
}

TEST(BvhErrors, AcceptsBlankLinesAndSignedNumbers) {
  const BvhData d =
      ParseExpectOk(Replace(Replace(kSmall, "0 1 2 3 4", "\n\n+0 1 2 -.5e1 4"), "Frames: 2", "Frames:   2"));
  ASSERT_TRUE(d.clip);
  EXPECT_NEAR(d.clip->joints[0].translation.values[0].x(), 0.0, 1e-15);
}

// The CMU file (shared data, absent in a user's clone).
class CmuBvh : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto text = test_util::ReadFileBytes(test_util::SharedData("bvh/cmu_01_01.bvh"));
    if (!text) GTEST_SKIP() << "shared data " << test_util::SharedData("bvh/cmu_01_01.bvh").string() << " is absent";
    text_ = *text;
    ref_ = testing::ReadRefBvh(text_);
    StatusOr<BvhData> d = ParseBvh(text_);
    ASSERT_TRUE(d.ok()) << d.status().message();
    data_ = *d;
  }
  std::string text_;
  RefBvh ref_;
  BvhData data_;
};

TEST_F(CmuBvh, SkeletonAndClipShape) {
  EXPECT_EQ(data_.skeleton->size(), 31u);
  EXPECT_EQ(data_.skeleton->names[0], "Hips");
  EXPECT_EQ(data_.skeleton->parents[0], -1);
  EXPECT_EQ(data_.clip->frame_count, 2752u);
  EXPECT_NEAR(data_.clip->frame_time, 1.0 / 120.0, 1e-6);
  EXPECT_NEAR(data_.clip->duration, 2751 * data_.clip->frame_time, 1e-12);
  ASSERT_EQ(ref_.joints.size(), 31u);
  for (size_t j = 0; j < 31; ++j) {
    EXPECT_EQ(data_.skeleton->names[j], ref_.joints[j].name);
    EXPECT_EQ(data_.skeleton->parents[j], ref_.joints[j].parent);
  }
  EXPECT_EQ(data_.skeleton->channels[0].size(), 6u);
  EXPECT_EQ(data_.skeleton->channels[1],
            (std::vector<Channel>{Channel::kZrotation, Channel::kYrotation, Channel::kXrotation}));
}

TEST_F(CmuBvh, WorldPositionsAtAndBetweenFramesMatchIndependentFk) {
  const double dt = ref_.frame_time;
  for (double x : {0.0, 1.0, 500.0, 1377.0, 2751.0, 0.3, 100.5, 2000.77, 2750.999}) {
    const double t = x * dt;
    const double d = MaxDistance(EnginePositionsAt(data_, t), testing::RefWorldPositionsAt(ref_, t));
    EXPECT_LT(d, 1e-6) << "frame " << x;
  }
}

TEST_F(CmuBvh, WriteThenReadWithin1e4) {
  const BvhData back = ParseExpectOk(WriteBvh(*data_.clip));
  ASSERT_TRUE(back.clip);
  EXPECT_EQ(back.skeleton->names, data_.skeleton->names);
  EXPECT_EQ(back.skeleton->channels, data_.skeleton->channels);
  EXPECT_EQ(back.clip->frame_count, 2752u);
  double worst = 0;
  for (size_t f = 0; f < 2752; f += 3) {
    const double t = f * data_.clip->frame_time;
    worst = std::max(worst, MaxDistance(EnginePositionsAt(back, t), EnginePositionsAt(data_, t)));
  }
  EXPECT_LT(worst, 1e-4);
}

// The writer re-expresses the same motion in any channel order and with any
// root OFFSET (position channels = translation − OFFSET).
TEST_F(CmuBvh, WriterReexpressesTheMotionInOtherOrdersAndRootOffset) {
  for (const std::string order : {"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"}) {
    auto sk = std::make_shared<Skeleton>(*data_.skeleton);
    for (auto& list : sk->channels) {
      std::vector<Channel> next;
      if (list.size() == 6) next = {Channel::kZposition, Channel::kXposition, Channel::kYposition};
      for (char a : order) next.push_back(static_cast<Channel>(static_cast<int>(Channel::kXrotation) + (a - 'X')));
      list = next;
    }
    sk->rest[0].translation = Eigen::Vector3d(4, -3, 7);
    Clip clip = *data_.clip;
    clip.skeleton = sk;
    const BvhData back = ParseExpectOk(WriteBvh(clip));
    ASSERT_TRUE(back.clip);
    EXPECT_EQ(back.skeleton->rest[0].translation, Eigen::Vector3d(4, -3, 7));
    EXPECT_EQ(back.skeleton->channels[3].size(), 3u);
    EXPECT_EQ(ChannelName(back.skeleton->channels[3][0]), std::string(1, order[0]) + "rotation");
    double worst = 0;
    for (size_t f = 0; f < 2752; f += 11) {
      const double t = f * data_.clip->frame_time;
      worst = std::max(worst, MaxDistance(EnginePositionsAt(back, t), EnginePositionsAt(data_, t)));
    }
    EXPECT_LT(worst, 1e-4) << order;
  }
}

TEST(BvhWriter, DefaultChannelsAndDepthFirstOrderForOtherSkeletons) {
  // Parents precede children but siblings interleave, as glTF allows.
  auto sk = std::make_shared<Skeleton>();
  sk->names = {"root", "a", "b", "a1", "b1"};
  sk->parents = {-1, 0, 0, 1, 2};
  sk->rest.resize(5);
  sk->rest[1].translation = {1, 0, 0};
  sk->rest[2].translation = {-1, 0, 0};
  sk->rest[3].translation = {0, 2, 0};
  sk->rest[4].translation = {0, 0, 3};
  sk->rest[2].rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()));  // rest rotation
  sk->channels.resize(5);
  sk->end_sites.resize(5);
  sk->end_sites[3] = Eigen::Vector3d(0, 1, 0);
  Clip clip;
  clip.skeleton = sk;
  clip.joints.resize(5);
  clip.duration = 1.0;
  clip.joints[0].translation = {{0, 1}, {{0, 0, 0}, {0, 3, 0}}};
  clip.joints[3].rotation = {{0, 1},
                             {Eigen::Quaterniond::Identity(),
                              Eigen::Quaterniond(Eigen::AngleAxisd(1.0, Eigen::Vector3d(1, 1, 0).normalized()))}};
  ASSERT_TRUE(clip.Validate().ok());
  const BvhData back = ParseExpectOk(WriteBvh(clip));
  ASSERT_TRUE(back.clip);
  EXPECT_EQ(back.skeleton->names, (std::vector<std::string>{"root", "a", "a1", "b", "b1"}));
  EXPECT_EQ(back.skeleton->channels[0].size(), 6u);
  EXPECT_EQ(back.skeleton->channels[2],
            (std::vector<Channel>{Channel::kZrotation, Channel::kXrotation, Channel::kYrotation}));
  EXPECT_EQ(back.skeleton->end_sites[2], Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(back.clip->frame_count, 31u);  // 1/30 s frames over 1 s
  EXPECT_NEAR(back.clip->frame_time, 1.0 / 30.0, 1e-15);
  std::vector<Trs> local(5);
  for (int f = 0; f <= 30; ++f) {
    const double t = f / 30.0;
    ASSERT_TRUE(SampleClip(clip, t, {}, local).ok());
    const auto original = EngineWorldPositions(*sk, local);
    const auto reread = EnginePositionsAt(back, t);
    for (size_t j = 0; j < 5; ++j) {
      const size_t k = static_cast<size_t>(back.skeleton->Find(sk->names[j]));
      EXPECT_LT((reread[k] - original[j]).norm(), 1e-5) << sk->names[j] << " frame " << f;
    }
  }
}

}  // namespace
}  // namespace armature
