// Whole-file reads and atomic writes in a data dir, and the errors they report.
#include "server/assets/file_io.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <gtest/gtest.h>
#include <set>

#include "../testing/temp_store.h"

namespace armature::server {
namespace {

namespace fs = std::filesystem;
using test_util::TempDir;

size_t EntriesIn(const fs::path& dir) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++n;
  return n;
}

TEST(FileIo, AnAtomicWriteReadsBackAndReplacesWithoutLeavingTemporaries) {
  TempDir dir;
  const std::string bytes("a\0b\nc", 5);  // binary-safe
  ASSERT_TRUE(WriteFileAtomic(dir.path(), "one.bin", bytes).ok());
  EXPECT_EQ(*ReadFile(dir.path() / "one.bin"), bytes);
  ASSERT_TRUE(WriteFileAtomic(dir.path(), "one.bin", "shorter").ok());
  EXPECT_EQ(*ReadFile(dir.path() / "one.bin"), "shorter");
  EXPECT_EQ(EntriesIn(dir.path()), 1u);
}

TEST(FileIo, AWriteThatFailsNamesTheDirAndTheFileButNoTemporary) {
  TempDir dir;
  const Status st = WriteFileAtomic(dir.path(), "missing/one.bin", "x");
  EXPECT_EQ(st.code(), StatusCode::kInternal);
  EXPECT_EQ(st.message(),
            "data dir " + dir.path().string() + ": cannot write missing/one.bin: " + std::strerror(ENOENT));
  EXPECT_EQ(EntriesIn(dir.path()), 0u);
}

TEST(FileIo, AFullDiskOrQuotaIsResourceExhaustedOtherErrorsInternal) {
  const fs::path dir = "/data";
  for (int err : {ENOSPC, EDQUOT}) {
    const Status st = DataDirError(dir, err, "write x");
    EXPECT_EQ(st.code(), StatusCode::kResourceExhausted);
    EXPECT_EQ(st.message(), "data dir /data: no space left on device");
  }
  const Status denied = DataDirError(dir, EACCES, "write manifest.json");
  EXPECT_EQ(denied.code(), StatusCode::kInternal);
  EXPECT_EQ(denied.message(), std::string("data dir /data: cannot write manifest.json: ") + std::strerror(EACCES));
}

TEST(FileIo, AMissingFileIsNotFoundNamingItsPath) {
  TempDir dir;
  const auto read = ReadFile(dir.path() / "nope");
  EXPECT_EQ(read.status().code(), StatusCode::kNotFound);
  EXPECT_EQ(read.status().message(), "cannot read " + (dir.path() / "nope").string());
}

TEST(FileIo, RandomSuffixesAreHexAndDoNotRepeat) {
  std::set<std::string> seen;
  for (int i = 0; i < 100; ++i) {
    const std::string s = RandomSuffix();
    EXPECT_FALSE(s.empty());
    EXPECT_EQ(s.find_first_not_of("0123456789abcdef"), std::string::npos) << s;
    seen.insert(s);
  }
  EXPECT_EQ(seen.size(), 100u);
}

TEST(FileIo, AnAllocatedFileHoldsItsBytesOnDisk) {
  TempDir dir;
  const fs::path path = dir.path() / "reserve";
  ASSERT_TRUE(AllocateFile(path, 100000));
  struct stat st {};
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_size, 100000);
  EXPECT_GE(static_cast<int64_t>(st.st_blocks) * 512, 100000);  // allocated, not sparse
  EXPECT_FALSE(AllocateFile(dir.path() / "missing" / "reserve", 10));
}

}  // namespace
}  // namespace armature::server
