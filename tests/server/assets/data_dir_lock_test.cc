// The data dir's flock: exclusive excludes everyone, shared only writers,
// across threads of one process too (each lock opens its own description).
#include "server/assets/data_dir_lock.h"

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <optional>

#include "../testing/temp_store.h"

namespace armature::server {
namespace {

using Mode = DataDirLock::Mode;
using test_util::TempDir;
constexpr auto kBlocked = std::chrono::milliseconds(100);
constexpr auto kGranted = std::chrono::seconds(10);

// Takes the lock in another thread and holds it until the future is read.
std::future<bool> AcquireElsewhere(const std::filesystem::path& dir, Mode mode) {
  return std::async(std::launch::async, [dir, mode] { return DataDirLock::Acquire(dir, mode).ok(); });
}

TEST(DataDirLock, AnExclusiveLockWaitsForTheHolderToRelease) {
  TempDir dir;
  std::optional<StatusOr<DataDirLock>> held(DataDirLock::Acquire(dir.path(), Mode::kExclusive));
  ASSERT_TRUE(held->ok()) << held->status().message();
  EXPECT_TRUE(std::filesystem::exists(dir.path() / ".lock"));
  auto other = AcquireElsewhere(dir.path(), Mode::kExclusive);
  EXPECT_EQ(other.wait_for(kBlocked), std::future_status::timeout);
  held.reset();  // released
  ASSERT_EQ(other.wait_for(kGranted), std::future_status::ready);
  EXPECT_TRUE(other.get());
}

TEST(DataDirLock, SharedLocksAreHeldTogetherButExcludeAWriter) {
  TempDir dir;
  std::optional<StatusOr<DataDirLock>> reader(DataDirLock::Acquire(dir.path(), Mode::kShared));
  ASSERT_TRUE(reader->ok());
  auto second_reader = AcquireElsewhere(dir.path(), Mode::kShared);
  ASSERT_EQ(second_reader.wait_for(kGranted), std::future_status::ready);
  EXPECT_TRUE(second_reader.get());
  auto writer = AcquireElsewhere(dir.path(), Mode::kExclusive);
  EXPECT_EQ(writer.wait_for(kBlocked), std::future_status::timeout);
  reader.reset();
  ASSERT_EQ(writer.wait_for(kGranted), std::future_status::ready);
  EXPECT_TRUE(writer.get());
}

TEST(DataDirLock, AMissingDirIsInternalNamingTheLockFile) {
  TempDir dir;
  const auto missing = dir.path() / "no" / "such";
  const auto lock = DataDirLock::Acquire(missing, Mode::kExclusive);
  EXPECT_EQ(lock.status().code(), StatusCode::kInternal);
  EXPECT_EQ(lock.status().message(), "cannot open " + (missing / ".lock").string() + ": No such file or directory");
}

}  // namespace
}  // namespace armature::server
