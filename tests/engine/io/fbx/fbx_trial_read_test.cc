// assimp reads an FBX file in a child process first (fbx_trial_read.cc):
// what libassimp 5.2 leaks when its reader throws stays there.
#include <malloc.h>

#include <string>

#include <gtest/gtest.h>

#include "armature/engine/io/asset.h"

namespace armature {
namespace {

// An ASCII FBX of `models` nodes, cut off inside its Objects scope.
std::string TruncatedFbx(int models) {
  std::string fbx = "; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n\tFBXVersion: 7400\n}\nObjects:  {\n";
  for (int i = 1; i <= models; ++i)
    fbx += "\tModel: " + std::to_string(i) + ", \"Model::Joint" + std::to_string(i) + "\", \"Null\" {\n\t}\n";
  return fbx;
}

// Bytes in use on the main thread's heap (gtest runs tests on it).
size_t HeapInUse() { return mallinfo2().uordblks; }

// Each failed read in this process leaked about 3 bytes for each byte of
// the file (the parser's elements and tokens): 20 reads of this 0.3 MB
// file kept 19.5 MB.
TEST(FbxTrialRead, AFailedReadLeavesNoMemoryBehind) {
  const std::string fbx = TruncatedFbx(6000);
  ASSERT_GT(fbx.size(), 250000u);
  auto first = ParseAsset(AssetFormat::kFbx, fbx, "cut");  // warms up what is made once
  ASSERT_FALSE(first.ok());
  EXPECT_EQ(first.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(first.status().message().rfind("FBX: ", 0), 0u) << first.status().message();
  const size_t before = HeapInUse();
  for (int i = 0; i < 20; ++i) {
    auto again = ParseAsset(AssetFormat::kFbx, fbx, "cut");
    ASSERT_FALSE(again.ok());
    EXPECT_EQ(again.status().message(), first.status().message());
  }
  const size_t after = HeapInUse();
  EXPECT_LT(after, before + (64u << 10)) << "grew " << (after - before) << " bytes over 20 failed reads";
}

}  // namespace
}  // namespace armature
