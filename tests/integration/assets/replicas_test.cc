// Two real servers on one data dir (as replicas on a ReadWriteMany volume)
// serve the same assets: what one imports or deletes, the other serves too
// (it polls the manifest), and concurrent imports on both keep every entry.
#include <atomic>
#include <csignal>
#include <cmath>
#include <fstream>
#include <set>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {
namespace fs = std::filesystem;

class Replicas : public ::testing::Test {
 protected:
  TempDir data_;
};

TEST_F(Replicas, ImportOnOneIsServedByTheOther) {
  ServerProcess a(data_.path(), {"--no-demo"});
  ServerProcess b(data_.path(), {"--no-demo"});
  client::Client ca(OptionsFor(a)), cb(OptionsFor(b));
  ASSERT_EQ(CodeOf([&] { cb.GetClip("arm"); }), grpc::StatusCode::NOT_FOUND);

  ca.Import({"arm.bvh", kArmBvh});
  EXPECT_TRUE(
      WaitFor([&] { return CodeOf([&] { cb.GetClip("arm"); }) == grpc::StatusCode::OK; }, kPropagationTimeoutSeconds))
      << ReadFile(b.log_file());
  // B evaluates it like A: the tip at t = 0.25 (the root turned 45° about Z).
  v1::EvaluateClipRequest r;
  r.set_clip("arm");
  r.add_times(0.25);
  r.set_space(v1::WORLD);
  const auto pa = ca.EvaluateClip(r), pb = cb.EvaluateClip(r);
  ASSERT_EQ(pb.poses(0).translations_size(), 6);
  EXPECT_NEAR(pb.poses(0).translations(4), 2 + 2 * std::sin(M_PI / 4), 1e-4);  // the default clip bound, in metres
  for (int i = 0; i < 6; ++i) EXPECT_EQ(pa.poses(0).translations(i), pb.poses(0).translations(i));
}

TEST_F(Replicas, DeleteOnOneDisappearsFromTheOther) {
  ServerProcess a(data_.path(), {"--no-demo"});
  client::Client ca(OptionsFor(a));
  ca.Import({"arm.bvh", kArmBvh});
  ca.Import({"keep.bvh", kArmBvh});
  ServerProcess b(data_.path(), {"--no-demo"});
  client::Client cb(OptionsFor(b));
  ASSERT_EQ(AssetNames(cb), (std::set<std::string>{"arm", "keep"}));

  cb.DeleteAsset("arm");
  EXPECT_TRUE(WaitFor([&] { return CodeOf([&] { ca.GetClip("arm"); }) == grpc::StatusCode::NOT_FOUND; },
                      kPropagationTimeoutSeconds))
      << ReadFile(a.log_file());
  EXPECT_EQ(AssetNames(ca), (std::set<std::string>{"keep"}));
  // The untouched asset is still served by A from memory, without a reparse.
  EXPECT_EQ(ca.GetClip("keep").frames(), 3);
  EXPECT_EQ(ReadFile(a.log_file()).find("asset 'keep' loaded"), std::string::npos) << ReadFile(a.log_file());
}

TEST_F(Replicas, ConcurrentImportsOnBothKeepEveryEntry) {
  ServerProcess a(data_.path(), {"--no-demo"});
  ServerProcess b(data_.path(), {"--no-demo"});
  constexpr int kEach = 12;
  auto import_all = [&](const ServerProcess& server, const std::string& prefix) {
    client::Client client(OptionsFor(server));
    for (int i = 0; i < kEach; ++i) client.Import({prefix + std::to_string(i) + ".bvh", kArmBvh});
  };
  std::thread ta([&] { import_all(a, "a"); });
  std::thread tb([&] { import_all(b, "b"); });
  ta.join();
  tb.join();

  std::set<std::string> expected;
  for (int i = 0; i < kEach; ++i) expected.insert({"a" + std::to_string(i), "b" + std::to_string(i)});
  // The manifest on disk names all of them, each with its file.
  const auto manifest = nlohmann::json::parse(ReadFile(data_.path() / "manifest.json"));
  std::set<std::string> listed;
  for (const auto& entry : manifest["assets"]) {
    listed.insert(entry["name"].get<std::string>());
    EXPECT_TRUE(fs::exists(data_.path() / entry["file"].get<std::string>())) << entry.dump();
  }
  EXPECT_EQ(listed, expected);
  // Both servers serve all of them.
  client::Client ca(OptionsFor(a)), cb(OptionsFor(b));
  EXPECT_TRUE(
      WaitFor([&] { return AssetNames(ca) == expected && AssetNames(cb) == expected; }, kPropagationTimeoutSeconds));
  EXPECT_EQ(AssetNames(ca), expected);
  EXPECT_EQ(AssetNames(cb), expected);
  // A name taken on one is taken on the other, even before B has reloaded.
  EXPECT_EQ(CodeOf([&] { cb.Import({"a0.bvh", kArmBvh}); }), grpc::StatusCode::ALREADY_EXISTS);
}

// Imports write their files and manifest under the data dir lock, so a
// replica that starts (and takes the lock to clean up) never finds another
// one between those writes: it removes every unlisted file at once, and
// never one of an import in progress.
TEST_F(Replicas, AStartingReplicaRemovesLeftoversButNoImportInProgress) {
  ServerProcess a(data_.path(), {"--no-demo"});
  client::Client ca(OptionsFor(a));
  ca.Import({"arm.bvh", kArmBvh});
  const fs::path leftover = data_.path() / "files" / "killed.0123.bvh";
  std::ofstream(leftover) << kArmBvh;
  // A imports all the while B starts, cleans up and stops, three times over.
  std::atomic<bool> done{false};
  std::set<std::string> acknowledged = {"arm"};
  std::thread importer([&] {
    for (int i = 0; !done && i < 500; ++i) {
      const std::string name = "busy" + std::to_string(i);
      ca.Import({name + ".bvh", kArmBvh});
      acknowledged.insert(name);
    }
  });
  for (int round = 0; round < 3; ++round) {
    ServerProcess b(data_.path(), {"--no-demo"});
    if (round == 0) EXPECT_FALSE(fs::exists(leftover)) << "a fresh leftover survived a start";
    EXPECT_EQ(b.Stop(SIGTERM), 0);
  }
  done = true;
  importer.join();
  // Every acknowledged import kept its file: a fresh server loads them all.
  ServerProcess c(data_.path(), {"--no-demo"});
  client::Client cc(OptionsFor(c));
  EXPECT_EQ(AssetNames(cc), acknowledged);
  EXPECT_EQ(ReadFile(c.log_file()).find("could not be loaded"), std::string::npos) << ReadFile(c.log_file());
}

}  // namespace
}  // namespace armature::testing
