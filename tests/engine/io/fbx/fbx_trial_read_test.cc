// assimp reads an FBX file in a child process first (fbx_trial_read.cc):
// what libassimp 5.2 leaks when its reader throws stays there.
#include <malloc.h>
#include <signal.h>
#include <sys/resource.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "armature/engine/io/asset.h"
#include "io/fbx/fbx_importer.h"
#include "../../testing/test_files.h"

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

// A crash in assimp ends only the reader's process. ParseFbx refuses this
// file before any read (fbx_structure.cc); read anyway, 100,000 nested
// scopes overflow assimp's recursive parser's stack, as 30,000 ended the
// whole process before the scan.
TEST(FbxTrialRead, ACrashInAssimpEndsOnlyTheReader) {
  std::string braces = "; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n\tFBXVersion: 7400\n}\nFoo:  {\n";
  for (int i = 0; i < 100000; ++i) braces += "a: {";
  braces += std::string(100000, '}') + "\n}\n";
  // The reader's stack is this thread's: at most 8 MB (the default), so the
  // overflow happens wherever the suite runs (the child inherits the limit).
  rlimit stack{};
  ASSERT_EQ(getrlimit(RLIMIT_STACK, &stack), 0);
  const rlimit before = stack;
  if (stack.rlim_cur == RLIM_INFINITY || stack.rlim_cur > (rlim_t{8} << 20)) stack.rlim_cur = rlim_t{8} << 20;
  ASSERT_EQ(setrlimit(RLIMIT_STACK, &stack), 0);
  const Status crashed = fbx_internal::TrialRead(braces, fbx_internal::TrialReadMemory(ImportLimits{}));
  setrlimit(RLIMIT_STACK, &before);
  ASSERT_FALSE(crashed.ok());
  EXPECT_EQ(crashed.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(crashed.message(), "FBX: assimp's reader crashed on the file (signal " + std::to_string(SIGSEGV) + ")");
  // This process goes on: the next file reads.
  const auto pivots = test_util::ReadFileBytes(std::filesystem::path(ARMATURE_TEST_DIR) / "data/fbx/pivots.fbx");
  ASSERT_TRUE(pivots.has_value());
  const Status read = fbx_internal::TrialRead(std::string(pivots->begin(), pivots->end()),
                                              fbx_internal::TrialReadMemory(ImportLimits{}));
  EXPECT_TRUE(read.ok()) << read.message();
}

// The reader's memory is bounded: an allocation past what it may take
// ends it with RESOURCE_EXHAUSTED (assimp would catch the bad_alloc), and
// the same file reads with room to spare.
TEST(FbxTrialRead, AReadPastItsMemoryIsRefused) {
  if (!fbx_internal::kTrialReadLimitsMemory) GTEST_SKIP() << "a sanitizer's build: the reader's memory is not capped";
  const auto pivots = test_util::ReadFileBytes(std::filesystem::path(ARMATURE_TEST_DIR) / "data/fbx/pivots.fbx");
  ASSERT_TRUE(pivots.has_value());
  std::string fbx(pivots->begin(), pivots->end());
  // 600,000 vertices (3.6 MB of text): assimp's tokens for them take about
  // 240 MB, far more than this process can hold freed (the cap is on the
  // address space's growth, and freed memory is reused within it).
  const std::string small = "Vertices: *9 {\n\t\t\ta: 0,0,0,1,0,0,0,1,0";
  const size_t at = fbx.find(small);
  ASSERT_NE(at, std::string::npos);
  std::string big = "Vertices: *1800000 {\n\t\t\ta: 0,0,0,1,0,0,0,1,0";
  for (int i = 3; i < 600000; ++i) big += ",0,0,0";
  fbx.replace(at, small.size(), big);
  const Status cramped = fbx_internal::TrialRead(fbx, uint64_t{8} << 20);
  ASSERT_FALSE(cramped.ok());
  EXPECT_EQ(cramped.code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(cramped.message(),
            "FBX: assimp's read of the file needs over 8388608 bytes of memory, the most one FBX read may take (twice "
            "the import limit max_decoded_bytes, at least 64 MB)");
  const Status roomy = fbx_internal::TrialRead(fbx, fbx_internal::TrialReadMemory(ImportLimits{}));
  EXPECT_TRUE(roomy.ok()) << roomy.message();
  EXPECT_EQ(fbx_internal::TrialReadMemory(ImportLimits{}), uint64_t{2} << 30);
  ImportLimits little;
  little.max_decoded_bytes = 1000;
  EXPECT_EQ(fbx_internal::TrialReadMemory(little), uint64_t{64} << 20);
}

}  // namespace
}  // namespace armature
