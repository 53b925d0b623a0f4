// BVH import and export against hostile input: limits applied while parsing,
// tracks only where the file pays for them, extra frame lines tolerated,
// names that are not UTF-8 refused, linear-size export of deep skeletons and
// export sizes known (and capped) before any work.
#include <chrono>
#include <string>

#include <gtest/gtest.h>

#include "armature/engine/io/asset.h"
#include "armature/engine/io/bvh/bvh.h"
#include "armature/base/utf8.h"

namespace armature {
namespace {

// Root with 6 channels, a channel-less "Chest" and a 3-channel "Neck".
std::string Bvh(const std::string& frames_line, const std::string& frame_lines, const std::string& chest = "Chest") {
  return "HIERARCHY\n"                                                                 // 1
         "ROOT Hips\n"                                                                 // 2
         "{\n"                                                                         // 3
         "  OFFSET 0 0 0\n"                                                            // 4
         "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"  // 5
         "  JOINT " +
         chest +
         "\n"                                                // 6
         "  {\n"                                             // 7
         "    OFFSET 0 5 0\n"                                // 8
         "    JOINT Neck\n"                                  // 9
         "    {\n"                                           // 10
         "      OFFSET 0 1 0\n"                              // 11
         "      CHANNELS 3 Zrotation Xrotation Yrotation\n"  // 12
         "      End Site\n"                                  // 13
         "      {\n"                                         // 14
         "        OFFSET 0 3 0\n"                            // 15
         "      }\n"                                         // 16
         "    }\n"                                           // 17
         "  }\n"                                             // 18
         "}\n"                                               // 19
         "MOTION\n"                                          // 20
         + frames_line +
         "\n"                 // 21
         "Frame Time: 0.1\n"  // 22
         + frame_lines;       // 23…
}

const std::string kTwoFrames = "0 1 2 3 4 5 6 7 8\n1 2 3 4 5 6 7 8 9\n";

TEST(BvhHardening, ExtraFrameLinesAreIgnoredWithAWarning) {
  // As assimp's Boxing_Toes.bvh: one frame line more than "Frames:" declares.
  auto asset = ParseAsset(AssetFormat::kBvh, Bvh("Frames: 1", kTwoFrames), "boxing");
  ASSERT_TRUE(asset.ok()) << asset.status().message();
  EXPECT_EQ(asset->clips[0].clip->frame_count, 1u);
  EXPECT_EQ(asset->clips[0].clip->joints[0].rotation.times.size(), 1u);
  ASSERT_EQ(asset->warnings.size(), 1u);
  EXPECT_EQ(asset->warnings[0], "line 24: 1 frame line beyond Frames: 1 ignored");

  auto three = ParseBvh(Bvh("Frames: 1", kTwoFrames + "\n2 3 4 5 6 7 8 9 10\n"));
  ASSERT_TRUE(three.ok()) << three.status().message();
  ASSERT_EQ(three->warnings.size(), 1u);
  EXPECT_EQ(three->warnings[0], "line 24: 2 frame lines beyond Frames: 1 ignored");
}

TEST(BvhHardening, FewerFrameLinesThanDeclaredIsStillAnError) {
  auto d = ParseBvh(Bvh("Frames: 3", kTwoFrames));
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(d.status().message().find("file ends after 2 of the 3 frames that 'Frames:' on line 21"), std::string::npos)
      << d.status().message();
}

TEST(BvhHardening, OnlyJointsWithChannelsGetTracks) {
  auto d = ParseBvh(Bvh("Frames: 2", kTwoFrames));
  ASSERT_TRUE(d.ok()) << d.status().message();
  const Clip& c = *d->clip;
  ASSERT_EQ(c.joints.size(), 3u);
  EXPECT_EQ(c.joints[0].rotation.values.size(), 2u);
  EXPECT_EQ(c.joints[0].translation.values.size(), 2u);
  EXPECT_TRUE(c.joints[1].rotation.empty());  // Chest: no CHANNELS
  EXPECT_TRUE(c.joints[1].rotation.values.empty());
  EXPECT_TRUE(c.joints[1].translation.empty());
  EXPECT_EQ(c.joints[2].rotation.values.size(), 2u);
  EXPECT_TRUE(c.joints[2].translation.empty());
  // The channel-less joint samples at its rest pose.
  std::vector<Trs> pose(3);
  ASSERT_TRUE(SampleClip(c, 0.05, {}, pose).ok());
  EXPECT_EQ(pose[1].translation, Eigen::Vector3d(0, 5, 0));
  EXPECT_TRUE(pose[1].rotation.isApprox(Eigen::Quaterniond::Identity()));
}

TEST(BvhHardening, FrameLimitIsAppliedAtTheFramesLine) {
  // A lying count is refused at once, not after reading (or failing to read) the frames.
  auto d = ParseBvh(Bvh("Frames: 5000000", kTwoFrames));
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.status().code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(d.status().message(),
            "line 21: 5000000 frames (Frames:) is over the import limit max_clip_frames = 1000000");

  ImportLimits limits;
  limits.max_clip_frames = 1;
  auto small = ParseBvh(Bvh("Frames: 2", kTwoFrames), limits);
  ASSERT_FALSE(small.ok());
  EXPECT_EQ(small.status().code(), StatusCode::kResourceExhausted);
  EXPECT_NE(small.status().message().find("max_clip_frames = 1"), std::string::npos) << small.status().message();
}

TEST(BvhHardening, FramesTimesTracksIsCappedBeforeReading) {
  ImportLimits limits;
  limits.max_clip_keys = 5;  // 2 frames × 3 tracks (root rotation, root translation, neck rotation) = 6
  auto d = ParseBvh(Bvh("Frames: 2", kTwoFrames), limits);
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.status().code(), StatusCode::kResourceExhausted);
  EXPECT_NE(d.status().message().find("line 21: 2 frames × 3 tracks = 6 is over the import limit max_clip_keys = 5"),
            std::string::npos)
      << d.status().message();
  limits.max_clip_keys = 6;
  EXPECT_TRUE(ParseBvh(Bvh("Frames: 2", kTwoFrames), limits).ok());
}

TEST(BvhHardening, ManyChannelLessJointsCostNoKeys) {
  // 20 000 joints without channels under a 1-channel root, 2000 frames: the
  // old reader stored a rotation for every joint in every frame (40M keys).
  std::string text = "HIERARCHY\nROOT R\n{\nOFFSET 0 0 0\nCHANNELS 1 Zrotation\n";
  for (int j = 0; j < 20000; ++j) text += "JOINT j" + std::to_string(j) + "\n{\nOFFSET 0 1 0\n}\n";
  text += "}\nMOTION\nFrames: 2000\nFrame Time: 0.01\n";
  for (int f = 0; f < 2000; ++f) text += "1\n";
  const auto start = std::chrono::steady_clock::now();
  auto d = ParseBvh(text);
  ASSERT_TRUE(d.ok()) << d.status().message();
  size_t keys = 0;
  for (const JointTrack& t : d->clip->joints) keys += t.rotation.values.size() + t.translation.values.size();
  EXPECT_EQ(keys, 2000u);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
}

TEST(BvhHardening, JointNamesMustBeUtf8) {
  auto d = ParseBvh(Bvh("Frames: 2", kTwoFrames,
                        "Ch\xff"
                        "est"));
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(d.status().message(), "line 6: joint name 'Ch\\xffest' is not valid UTF-8");
  // Valid multi-byte names are fine.
  EXPECT_TRUE(ParseBvh(Bvh("Frames: 2", kTwoFrames, "Brust_\xc3\xa4")).ok());
}

TEST(BvhHardening, MessagesQuotingInputAreUtf8) {
  std::string bad = Bvh("Frames: 2", kTwoFrames);
  bad.replace(bad.find("OFFSET 0 5 0"), 12, "OFFSET 0 \xfe\xff 0");
  auto d = ParseBvh(bad);
  ASSERT_FALSE(d.ok());
  EXPECT_TRUE(IsValidUtf8(d.status().message())) << d.status().message();
  EXPECT_NE(d.status().message().find("'\\xfe\\xff'"), std::string::npos) << d.status().message();
}

// A chain of `depth` joints with one rotation channel each, one frame.
std::shared_ptr<const Clip> Chain(size_t depth) {
  std::string text = "HIERARCHY\n";
  for (size_t j = 0; j < depth; ++j)
    text += (j == 0 ? "ROOT j" : "JOINT j") + std::to_string(j) + "\n{\nOFFSET 0 1 0\nCHANNELS 1 Zrotation\n";
  for (size_t j = 0; j < depth; ++j) text += "}\n";
  text += "MOTION\nFrames: 1\nFrame Time: 0.1\n";
  for (size_t j = 0; j < depth; ++j) text += "1 ";
  auto d = ParseBvh(text + "\n");
  EXPECT_TRUE(d.ok()) << d.status().message();
  return d.ok() ? d->clip : nullptr;
}

TEST(BvhWriterHardening, DeepSkeletonsExportInLinearSize) {
  const auto shallow = Chain(1000), deep = Chain(20000);
  ASSERT_TRUE(shallow && deep);
  const std::string a = WriteBvh(*shallow), b = WriteBvh(*deep);
  ASSERT_FALSE(a.empty());
  ASSERT_FALSE(b.empty());
  // 20× the joints: about 20× the bytes (tabs used to grow with depth: 400×).
  EXPECT_LT(static_cast<double>(b.size()) / a.size(), 25.0) << a.size() << " " << b.size();
  auto back = ParseBvh(b);
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_EQ(back->skeleton->size(), 20000u);
  EXPECT_EQ(back->skeleton->parents[19999], 19998);
}

TEST(BvhWriterHardening, FrameCountIsKnownUpFrontAndCapped) {
  auto clip = std::make_shared<Clip>(*Chain(2));
  // Keys at 0 and 1e6 s, no frame time: the writer samples at 30 fps.
  for (JointTrack& t : clip->joints) {
    t.rotation.times = {0.0, 1e6};
    t.rotation.values = {Eigen::Quaterniond::Identity(), Eigen::Quaterniond::Identity()};
  }
  clip->frame_time = 0;
  clip->frame_count = 2;
  clip->duration = 1e6;
  ASSERT_TRUE(clip->Validate().ok());
  EXPECT_EQ(BvhExportFrameCount(*clip), 30000001u);
  EXPECT_GT(BvhExportByteEstimate(*clip), 30000001u * 2 * 8);
  const auto start = std::chrono::steady_clock::now();
  auto out = ExportBvh(*clip);
  ASSERT_FALSE(out.ok());
  EXPECT_EQ(out.status().code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(out.status().message(), "BVH export would write 30000001 frames, over the limit of 1000000");
  EXPECT_TRUE(WriteBvh(*clip).empty());
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));

  clip->duration = 1e300;  // saturates instead of wrapping
  EXPECT_EQ(BvhExportFrameCount(*clip), UINT64_MAX);
  EXPECT_EQ(BvhExportByteEstimate(*clip), UINT64_MAX);

  clip->duration = 1.0;
  EXPECT_EQ(BvhExportFrameCount(*clip), 31u);
  auto small = ExportBvh(*clip, 31);
  ASSERT_TRUE(small.ok()) << small.status().message();
  EXPECT_LE(small->size(), BvhExportByteEstimate(*clip));
  EXPECT_EQ(ExportBvh(*clip, 30).status().code(), StatusCode::kResourceExhausted);
}

TEST(BvhWriterHardening, NamesFromOtherFormatsAreWrittenSoTheyReadBack) {
  // glTF node names can hold line breaks, blanks at the ends and a trailing '{'.
  auto clip = std::make_shared<Clip>(*Chain(4));
  auto sk = std::make_shared<Skeleton>(*clip->skeleton);
  sk->names = {"a\nb", " pad ", "brace{", "a_b"};
  clip->skeleton = sk;
  const std::string text = WriteBvh(*clip);
  ASSERT_FALSE(text.empty());
  auto back = ParseBvh(text);
  ASSERT_TRUE(back.ok()) << back.status().message() << "\n" << text;
  EXPECT_EQ(back->skeleton->names, (std::vector<std::string>{"a_b", "pad", "brace{_", "a_b_3"}));
}

}  // namespace
}  // namespace armature
