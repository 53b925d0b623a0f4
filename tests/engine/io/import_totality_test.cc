// Every input gets an answer: ParseAsset and DetectFormat return a Status
// promptly for any bytes (random, bit-flipped real files), never throw, and
// their messages are UTF-8 whatever the input held. Also the UTF-8 helpers
// the importers and the server quote input through.
#include <chrono>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "armature/engine/io/asset.h"
#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/demo_walk.h"
#include "armature/base/utf8.h"

namespace armature {
namespace {

TEST(Utf8, ValidatesWellFormedSequencesOnly) {
  EXPECT_TRUE(IsValidUtf8(""));
  EXPECT_TRUE(IsValidUtf8("Hips"));
  EXPECT_TRUE(IsValidUtf8("\xc3\xa4\xe2\x82\xac\xf0\x9f\x98\x80"));  // ä € 😀
  EXPECT_FALSE(IsValidUtf8("\xff"));
  EXPECT_FALSE(IsValidUtf8("\xc3"));              // truncated
  EXPECT_FALSE(IsValidUtf8("\xc0\xaf"));          // overlong '/'
  EXPECT_FALSE(IsValidUtf8("\xed\xa0\x80"));      // surrogate U+D800
  EXPECT_FALSE(IsValidUtf8("\xf4\x90\x80\x80"));  // above U+10FFFF
  EXPECT_FALSE(IsValidUtf8(std::string("a\x80", 2)));
}

TEST(Utf8, EscapeForMessageEscapesBadBytesControlsAndBackslashAndCuts) {
  EXPECT_EQ(EscapeForMessage("Hips"), "Hips");
  EXPECT_EQ(EscapeForMessage("Ch\xff"
                             "est"),
            "Ch\\xffest");
  EXPECT_EQ(EscapeForMessage(std::string("a\0b\n\\", 5)), "a\\x00b\\x0a\\x5c");
  EXPECT_EQ(EscapeForMessage("\xc3\xa4"), "\xc3\xa4");
  EXPECT_EQ(EscapeForMessage("abcdef", 3), "abc...");
  EXPECT_EQ(EscapeForMessage("\xc3\xa4\xc3\xa4", 3), "\xc3\xa4\\xc3...");  // a cut sequence is escaped
  std::mt19937 rng(7);
  for (int i = 0; i < 2000; ++i) {
    std::string s(rng() % 40, '\0');
    for (char& c : s) c = static_cast<char>(rng());
    EXPECT_TRUE(IsValidUtf8(EscapeForMessage(s)));
  }
}

// Imports `bytes` as every format and by detection; each call must answer
// quickly with a UTF-8 message.
void ExpectAnswered(const std::string& bytes, const std::string& filename) {
  for (AssetFormat f :
       {AssetFormat::kBvh, AssetFormat::kGltf, AssetFormat::kGlb, AssetFormat::kObj, AssetFormat::kFbx}) {
    const auto start = std::chrono::steady_clock::now();
    auto r = ParseAsset(f, bytes, "x");
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5)) << FormatName(f);
    if (!r.ok()) EXPECT_TRUE(IsValidUtf8(r.status().message())) << FormatName(f) << ": " << r.status().message();
  }
  auto format = DetectFormat("", filename, bytes);
  if (!format.ok()) EXPECT_TRUE(IsValidUtf8(format.status().message())) << format.status().message();
}

TEST(ImportTotality, RandomBytesAreAnsweredWithUtf8Messages) {
  std::mt19937 rng(42);
  for (int i = 0; i < 300; ++i) {
    std::string bytes(100, '\0');
    for (char& c : bytes) c = static_cast<char>(rng());
    if (i % 3 == 0) bytes.replace(0, 10, "HIERARCHY\n");
    if (i % 3 == 1) bytes.replace(0, 4, i % 2 ? "glTF" : "Kaydara FBX Binary  ");
    ExpectAnswered(bytes, i % 2 ? "x.bvh" : "x\xff.bin");
  }
}

TEST(ImportTotality, BitFlippedRealBvhIsAnswered) {
  const std::string bvh = WriteBvh(*MakeDemoWalk().clip);
  ASSERT_FALSE(bvh.empty());
  std::mt19937 rng(3);
  for (int i = 0; i < 40; ++i) {
    std::string bytes = bvh;
    for (int k = 0; k < 8; ++k) bytes[rng() % bytes.size()] ^= static_cast<char>(1 << (rng() % 8));
    ExpectAnswered(bytes, "walk.bin");
  }
}

TEST(ImportTotality, UnknownFormatValuesAreErrors) {
  auto r = ParseAsset(static_cast<AssetFormat>(99), "HIERARCHY", "x");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(r.status().message(), "unknown asset format 99");
  auto d = DetectFormat("b\xffh", "", "");
  ASSERT_FALSE(d.ok());
  EXPECT_TRUE(IsValidUtf8(d.status().message()));
  EXPECT_NE(d.status().message().find("'b\\xffh'"), std::string::npos) << d.status().message();
}

TEST(ImportTotality, UnknownInterpolationAndWrapValuesAreErrors) {
  auto clip = std::make_shared<Clip>(*MakeDemoWalk().clip);
  std::vector<Trs> pose(clip->skeleton->size());
  SampleOptions options;
  options.interpolation = static_cast<Interpolation>(99);
  auto st = SampleClip(*clip, 0.1, options, pose);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("interpolation 99 is not STEP, LINEAR or CUBIC"), std::string::npos) << st.message();
  options = {};
  options.wrap = static_cast<WrapMode>(7);
  EXPECT_EQ(SampleClip(*clip, 0.1, options, pose).code(), StatusCode::kInvalidArgument);
  clip->joints[0].rotation.interpolation = static_cast<Interpolation>(99);
  EXPECT_EQ(clip->Validate().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace armature
