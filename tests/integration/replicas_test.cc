// Two real servers on one data dir (as replicas on a ReadWriteMany volume)
// serve the same assets: what one imports or deletes, the other serves too
// (it polls the manifest), and concurrent imports on both keep every entry.
#include <cmath>
#include <fstream>
#include <set>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "client_helpers.h"
#include "server_process.h"

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
  Client ca(OptionsFor(a)), cb(OptionsFor(b));
  ASSERT_EQ(CodeOf([&] { cb.GetClip("arm"); }), grpc::StatusCode::NOT_FOUND);

  ca.Import({"arm.bvh", kArmBvh});
  EXPECT_TRUE(WaitFor([&] { return CodeOf([&] { cb.GetClip("arm"); }) == grpc::StatusCode::OK; },
                      kPropagationTimeoutSeconds))
      << ReadFile(b.log_file());
  // B evaluates it like A: the tip at t = 0.25 (the root turned 45° about Z).
  v1::EvaluateClipRequest r;
  r.set_clip("arm");
  r.add_times(0.25);
  r.set_space(v1::WORLD);
  const auto pa = ca.EvaluateClip(r), pb = cb.EvaluateClip(r);
  ASSERT_EQ(pb.poses(0).translations_size(), 6);
  EXPECT_NEAR(pb.poses(0).translations(4), 2 + 2 * std::sin(M_PI / 4), 1e-5);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(pa.poses(0).translations(i), pb.poses(0).translations(i));
}

TEST_F(Replicas, DeleteOnOneDisappearsFromTheOther) {
  ServerProcess a(data_.path(), {"--no-demo"});
  Client ca(OptionsFor(a));
  ca.Import({"arm.bvh", kArmBvh});
  ca.Import({"keep.bvh", kArmBvh});
  ServerProcess b(data_.path(), {"--no-demo"});
  Client cb(OptionsFor(b));
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
    Client client(OptionsFor(server));
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
  Client ca(OptionsFor(a)), cb(OptionsFor(b));
  EXPECT_TRUE(WaitFor([&] { return AssetNames(ca) == expected && AssetNames(cb) == expected; },
                      kPropagationTimeoutSeconds));
  EXPECT_EQ(AssetNames(ca), expected);
  EXPECT_EQ(AssetNames(cb), expected);
  // A name taken on one is taken on the other, even before B has reloaded.
  EXPECT_EQ(CodeOf([&] { cb.Import({"a0.bvh", kArmBvh}); }), grpc::StatusCode::ALREADY_EXISTS);
}

TEST_F(Replicas, AStartingReplicaKeepsAnotherOnesUnlistedFiles) {
  ServerProcess a(data_.path(), {"--no-demo"});
  Client(OptionsFor(a)).Import({"arm.bvh", kArmBvh});
  // As if A were between writing an import's file and listing it in the manifest.
  const fs::path pending = data_.path() / "files" / "pending.0123.bvh";
  std::ofstream(pending) << kArmBvh;
  ServerProcess b(data_.path(), {"--no-demo"});
  EXPECT_TRUE(fs::exists(pending));
  Client cb(OptionsFor(b));
  EXPECT_EQ(AssetNames(cb), std::set<std::string>{"arm"});
}

}  // namespace
}  // namespace armature::testing
