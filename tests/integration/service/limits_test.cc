// Configurable limits (RESOURCE_EXHAUSTED naming the limit) and names that
// could escape the data dir.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {
namespace fs = std::filesystem;

TEST(Limits, ClipFramesOverTheLimitAreRefusedAtImport) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-clip-frames", "40"});
  client::Client client(OptionsFor(server));
  const grpc::Status status = StatusOf([&] { client.Import({"long.bvh", ArmBvhWithFrames(41)}); });
  const std::string& message = status.error_message();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(message.find("41 frames"), std::string::npos) << message;
  EXPECT_NE(message.find("--max-clip-frames"), std::string::npos) << message;
  EXPECT_NE(message.find("long.bvh"), std::string::npos) << message;
  EXPECT_EQ(client.ListAssets().assets_size(), 0);
  EXPECT_EQ(client.Import({"ok.bvh", ArmBvhWithFrames(40)}).asset().clips(0).frames(), 40);
}

TEST(Limits, MessageSizeIsEnforcedBothWays) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-message-mb", "0.25"});
  client::Client client(OptionsFor(server));
  client.Import({"arm.bvh", kArmBvh});
  // 20000 world poses of 2 joints: about 20000 × 2 × 7 floats × 4 bytes = 1.1 MB, over 0.25 MiB.
  v1::EvaluateClipRequest r;
  r.set_clip("arm");
  for (int i = 0; i < 20000; ++i) r.add_times(i * 1e-4);
  EXPECT_EQ(CodeOf([&] { client.EvaluateClip(r); }), grpc::StatusCode::RESOURCE_EXHAUSTED);
  // A request over the server's receive limit.
  v1::EvaluateClipRequest big;
  big.set_clip("arm");
  for (int i = 0; i < 40000; ++i) big.add_times(0);
  EXPECT_EQ(CodeOf([&] { client.EvaluateClip(big); }), grpc::StatusCode::RESOURCE_EXHAUSTED);
  // The client's own receive limit.
  client::ClientOptions small = OptionsFor(server);
  small.max_message_bytes = 1000;
  r.clear_times();
  for (int i = 0; i < 100; ++i) r.add_times(0);
  EXPECT_EQ(CodeOf([&] { client::Client(small).EvaluateClip(r); }), grpc::StatusCode::RESOURCE_EXHAUSTED);
}

TEST(Limits, EveryLimitIsAFlagAndAnEnvironmentVariable) {
  TempDir data;
  for (const char* flag : {"--max-clip-frames", "--max-mesh-vertices", "--max-ik-iterations",
                           "--max-sessions-per-client", "--max-sessions"}) {
    try {
      ServerProcess refused(data.path(), {flag, "0"});
      ADD_FAILURE() << flag << " 0 was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(flag), std::string::npos) << e.what();
    }
  }
  const auto env = RunCommand(ShellQuote(ARMATURE_SERVER_BIN) + " --help");
  EXPECT_EQ(env.exit_code, 0);
  EXPECT_NE(env.out.find("ARMATURE_MAX_SESSIONS_PER_CLIENT"), std::string::npos) << env.out;
  const auto bad_env = RunCommand("ARMATURE_MAX_CLIP_FRAMES=0 " + ShellQuote(ARMATURE_SERVER_BIN) + " --data-dir " +
                                  ShellQuote(data.path().string()) + " --grpc-port 0 --http-port -1");
  EXPECT_NE(bad_env.exit_code, 0);
  EXPECT_NE((bad_env.out + bad_env.err).find("max-clip-frames"), std::string::npos) << bad_env.out << bad_env.err;
}

TEST(AssetNames, NothingEscapesTheDataDir) {
  TempDir root;
  const fs::path data = root.path() / "data";
  ServerProcess server(data, {"--no-demo"});
  client::Client client(OptionsFor(server));
  for (const std::string& name :
       std::vector<std::string>{"../evil", "/etc/passwd", "a/b", std::string("nul\0byte", 8), ".hidden", ".."}) {
    const grpc::Status status = StatusOf([&] { client.Import({"arm.bvh", kArmBvh}, name); });
    const std::string& message = status.error_message();
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << "name " << name;
    EXPECT_NE(message.find("name"), std::string::npos) << message;
  }
  // A file name with a path: only its stem names the asset.
  EXPECT_EQ(client.Import({"../../up/arm.bvh", kArmBvh}).asset().name(), "arm");
  // Resource uris that look like paths are stored under files/ with a safe name.
  const std::vector<client::UploadFile> resources = {
      {"../../escape.bin", "A"}, {"/tmp/absolute.bin", "B"}, {std::string("nul\0.bin", 8), "C"}, {"..", "D"}};
  const auto imported = client.Import({"res.bvh", kArmBvh}, "", "", false, resources);
  EXPECT_EQ(imported.asset().name(), "res");
  const auto manifest = nlohmann::json::parse(ReadFile(data / "manifest.json"));
  size_t stored = 0;
  for (const auto& entry : manifest["assets"]) {
    if (entry["name"] != "res") continue;
    ASSERT_EQ(entry["resources"].size(), resources.size()) << entry.dump();
    for (const auto& [uri, file] : entry["resources"].items()) {
      const fs::path p = fs::weakly_canonical(data / file.get<std::string>());
      EXPECT_EQ(p.parent_path(), fs::weakly_canonical(data / "files")) << uri << " → " << file;
      EXPECT_TRUE(fs::is_regular_file(p)) << p;
      ++stored;
    }
  }
  EXPECT_EQ(stored, resources.size());
  // Nothing was written beside or above the data dir.
  for (const auto& entry : fs::recursive_directory_iterator(root.path())) {
    if (!entry.is_regular_file()) continue;
    const fs::path rel = fs::relative(entry.path(), data);
    EXPECT_FALSE(rel.empty() || rel.native().starts_with("..")) << entry.path();
  }
}

}  // namespace
}  // namespace armature::testing
