// A full disk: imports fail with RESOURCE_EXHAUSTED naming the data dir and
// leave nothing behind, deletes still work (they are how a user frees
// space), and a restart loads every acknowledged asset. The data dir is a
// real 2 MiB tmpfs, so the server meets a real ENOSPC.
#include <sys/mount.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "armature/engine/io/demo_character.h"
#include "support/client_helpers.h"
#include "support/data_dir_check.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {
namespace fs = std::filesystem;

class DiskFull : public ::testing::Test {
 protected:
  void SetUp() override {
    data_ = scratch_.path() / "data";
    fs::create_directories(data_);
    if (::mount("tmpfs", data_.c_str(), "tmpfs", 0, "size=2m") != 0)
      GTEST_SKIP() << "cannot mount a 2 MiB tmpfs for the data dir (" << std::strerror(errno)
                   << "): the test needs root (CAP_SYS_ADMIN)";
    mounted_ = true;
    auto glb = MakeDemoCharacterGlb();
    ASSERT_TRUE(glb.ok()) << glb.status().message();
    character_ = SplitGlb(*glb, "body.bin");
  }
  void TearDown() override {
    server_.reset();
    if (mounted_) ::umount2(data_.c_str(), MNT_DETACH);
  }

  // Imports characters (a .gltf and its .bin) until the disk refuses one;
  // returns that refusal.
  grpc::Status FillUp(client::Client& client) {
    for (int i = 0; i < 100; ++i) {
      const std::string name = "c" + std::to_string(next_++);
      const grpc::Status st = StatusOf([&] {
        client.Import({name + ".gltf", character_.gltf}, "", "", false, {{"body.bin", character_.bin}});
      });
      if (!st.ok()) return st;
      acknowledged_.insert(name);
    }
    ADD_FAILURE() << "100 imports fit on a 2 MiB disk";
    return grpc::Status::OK;
  }

  void ExpectFullDiskError(const grpc::Status& st) {
    EXPECT_EQ(st.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << st.error_message();
    EXPECT_NE(st.error_message().find("data dir " + data_.string() + ": no space left on device"), std::string::npos)
        << st.error_message();
    EXPECT_EQ(st.error_message().find(".tmp-"), std::string::npos) << "names a temporary file: " << st.error_message();
  }

  void ExpectStoreMatches(client::Client& client) {
    EXPECT_EQ(AssetNames(client), acknowledged_);
    EXPECT_EQ(ManifestAssetNames(data_), acknowledged_);
    EXPECT_EQ(LeftoverFiles(data_), std::vector<std::string>{});
  }

  TempDir scratch_;
  fs::path data_;
  bool mounted_ = false;
  SplitGltf character_;
  std::optional<ServerProcess> server_;
  std::set<std::string> acknowledged_;
  int next_ = 0;
};

TEST_F(DiskFull, FailedImportsLeaveNothingAndDeletesStillWork) {
  server_.emplace(data_, std::vector<std::string>{"--no-demo"});
  client::Client client(OptionsFor(*server_));
  ExpectFullDiskError(FillUp(client));
  ASSERT_GE(acknowledged_.size(), 2u) << "the character should fit a few times on 2 MiB";
  ExpectStoreMatches(client);

  // The disk is full, yet a delete works: it is how space is freed.
  const std::string first = *acknowledged_.begin();
  EXPECT_EQ(client.DeleteAsset(first).name(), first);
  acknowledged_.erase(first);
  ExpectStoreMatches(client);

  // Full again, and this time without the reserve (as if another replica had
  // used it) and not one byte free: the delete still goes through.
  ExpectFullDiskError(FillUp(client));
  fs::remove(data_ / ".space-reserve");
  const fs::path filler = data_ / "filler";
  {
    std::ofstream out(filler, std::ios::binary);
    const std::string block(4096, 'x');
    for (int i = 0; i < 1024 && out.write(block.data(), block.size()); ++i) out.flush();
  }
  EXPECT_EQ(fs::space(data_).available, 0u);
  const std::string second = *acknowledged_.begin();
  EXPECT_EQ(client.DeleteAsset(second).name(), second);
  acknowledged_.erase(second);
  fs::remove(filler);
  ExpectStoreMatches(client);
  // What is stored still plays.
  for (const std::string& name : acknowledged_) EXPECT_GT(client.GetClip(name + ".walk").frames(), 10) << name;

  // A restart loads every acknowledged asset, and deletes go on working.
  ASSERT_EQ(server_->Stop(SIGTERM), 0);
  server_.emplace(data_, std::vector<std::string>{"--no-demo"});
  client::Client again(OptionsFor(*server_));
  ExpectStoreMatches(again);
  EXPECT_EQ(ReadFile(server_->log_file()).find("could not be loaded"), std::string::npos)
      << ReadFile(server_->log_file());
  ExpectFullDiskError(FillUp(again));
  const std::string third = *acknowledged_.rbegin();
  EXPECT_EQ(again.DeleteAsset(third).name(), third);
  acknowledged_.erase(third);
  ExpectStoreMatches(again);
}

}  // namespace
}  // namespace armature::testing
