// The foundation end to end: a real armature-server on a free port, driven
// through the client library and the CLI.
#include <signal.h>

#include <cmath>
#include <filesystem>
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

// The server keeps clips at its default bound, 0.01 cm on points 3 cm from each joint: 1e-4 in this
// arm's units (metres: its rest pose spans under 10), which each joint's position stays within.
constexpr double kClipBound = 1e-4;
namespace fs = std::filesystem;
using nlohmann::json;

class Foundation : public ::testing::Test {
 protected:
  TempDir data_;
  TempDir files_;
};

TEST_F(Foundation, ServesTheDemoWalkOnAFreshDataDir) {
  ServerProcess server(data_.path());
  client::Client client(OptionsFor(server));
  EXPECT_TRUE(client.Healthy());
  const auto clip = client.GetClip("demo_walk");
  EXPECT_GT(clip.duration(), 0.5);
  EXPECT_GT(clip.frames(), 10);
  // The demo walks: the root moves forward between two times a second apart.
  v1::EvaluateClipRequest r;
  r.set_clip("demo_walk");
  r.add_times(0);
  r.add_times(std::min(1.0, clip.duration()));
  r.set_space(v1::WORLD);
  const auto poses = client.EvaluateClip(r);
  ASSERT_EQ(poses.poses_size(), 2);
  const auto& a = poses.poses(0).translations();
  const auto& b = poses.poses(1).translations();
  const double moved = std::hypot(b[0] - a[0], b[2] - a[2]);
  EXPECT_GT(moved, 1e-3) << "the demo root should travel";
  // And through the CLI, as the README's tour does.
  const auto cli = RunCli(server.target(), {"pose", "demo_walk", "--time", "0.5", "--json"});
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  const json j = json::parse(cli.out);
  EXPECT_EQ(j["clip"], "demo_walk");
  EXPECT_EQ(j["space"], "world");
  EXPECT_EQ(j["joints"].size(), client.GetSkeleton("demo_walk").joints_size());
  EXPECT_TRUE(j["joints"][0]["parent"].is_null());
}

TEST_F(Foundation, ImportEvaluateStreamExportDeleteAndRestart) {
  const fs::path arm = WriteTemp(files_, "arm.bvh", kArmBvh);
  {
    ServerProcess server(data_.path(), {"--no-demo"});
    client::Client client(OptionsFor(server));
    const auto imported = client.ImportFile(arm);
    ASSERT_EQ(imported.asset().clips_size(), 1);
    EXPECT_EQ(imported.asset().clips(0).name(), "arm");
    EXPECT_EQ(imported.asset().clips(0).frames(), 3);
    EXPECT_DOUBLE_EQ(imported.asset().clips(0).duration(), 1.0);
    EXPECT_EQ(client.ListClips().clips_size(), 1);

    // World positions, hand-derived: the root at OFFSET (1,2,3), the tip 2
    // along the root's rotated X: at t=0.25 the root has turned 45° about Z.
    v1::EvaluateClipRequest r;
    r.set_clip("arm");
    for (double t : {0.0, 0.25, 0.5, 1.0}) r.add_times(t);
    r.set_space(v1::WORLD);
    const auto world = client.EvaluateClip(r);
    const double expected_angle[] = {0, M_PI / 4, M_PI / 2, M_PI};
    for (int i = 0; i < 4; ++i) {
      const auto& t = world.poses(i).translations();
      EXPECT_NEAR(t[0], 1, kClipBound);
      EXPECT_NEAR(t[3], 1 + 2 * std::cos(expected_angle[i]), kClipBound) << "time " << r.times(i);
      EXPECT_NEAR(t[4], 2 + 2 * std::sin(expected_angle[i]), kClipBound) << "time " << r.times(i);
      EXPECT_NEAR(t[5], 3, kClipBound);
    }
    // Subset of joints and local space.
    r.set_space(v1::LOCAL);
    r.add_joints("Tip");
    const auto local = client.EvaluateClip(r);
    ASSERT_EQ(local.joints_size(), 1);
    EXPECT_EQ(local.joints(0), 1);
    EXPECT_EQ(local.poses(0).translations_size(), 3);

    // A stream at 20 fps for 0.5 s of wall time: about 10 frames, in order, paced.
    v1::StreamClipRequest s;
    s.set_clip("arm");
    s.set_fps(20);
    s.set_loop(true);
    s.set_duration(0.5);
    std::vector<v1::PoseFrame> frames;
    client.StreamClip(s, [&](const v1::PoseFrame& f) {
      frames.push_back(f);
      return true;
    });
    ASSERT_EQ(frames.size(), 10u);
    EXPECT_EQ(frames[0].skeleton(), "arm");
    EXPECT_EQ(frames[0].joints_size(), 2);
    for (size_t i = 1; i < frames.size(); ++i) {
      EXPECT_EQ(frames[i].index(), i);
      EXPECT_NEAR(frames[i].time(), std::fmod(i / 20.0, 1.0), 1e-9);
      EXPECT_GE(frames[i].wall_time(), frames[i - 1].wall_time());
    }
    EXPECT_GE(frames.back().wall_time(), 0.4) << "frames must be paced in real time, not sent at once";

    // Export then re-import gives the same poses.
    const auto exported = client.ExportClip("arm");
    v1::ImportAssetResponse again = client.Import({"arm_copy.bvh", exported.data()}, "arm_copy");
    v1::EvaluateClipRequest rc = r;
    rc.set_clip("arm_copy");
    const auto copy = client.EvaluateClip(rc);
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(copy.poses(i).translations(k), local.poses(i).translations(k), 1e-4);

    EXPECT_EQ(client.DeleteAsset("arm_copy").name(), "arm_copy");
    EXPECT_EQ(CodeOf([&] { client.GetClip("arm_copy"); }), grpc::StatusCode::NOT_FOUND);
    EXPECT_EQ(server.Stop(SIGTERM), 0);
  }
  // Restart on the same data dir: everything is still there.
  ServerProcess server(data_.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  const auto clips = client.ListClips();
  ASSERT_EQ(clips.clips_size(), 1);
  EXPECT_EQ(clips.clips(0).name(), "arm");
  v1::EvaluateClipRequest r;
  r.set_clip("arm");
  r.add_times(0.25);
  r.set_space(v1::WORLD);
  EXPECT_NEAR(client.EvaluateClip(r).poses(0).translations(4), 2 + 2 * std::sin(M_PI / 4), kClipBound);
}

TEST_F(Foundation, BadInputGetsClearErrorsAndChangesNothing) {
  ServerProcess server(data_.path(), {"--no-demo", "--max-upload-mb", "1"});
  client::Client client(OptionsFor(server));
  client.Import({"arm.bvh", kArmBvh});
  const std::string before = client.ListAssets().SerializeAsString();

  // Malformed BVH: INVALID_ARGUMENT naming the file and the line.
  std::string broken = kArmBvh;
  broken.replace(broken.find("OFFSET 2 0 0"), 12, "OFFSETT 2 0 0");
  std::string message = MessageOf([&] { client.Import({"broken.bvh", broken}); });
  EXPECT_NE(message.find("broken.bvh"), std::string::npos) << message;
  EXPECT_NE(message.find("line 8"), std::string::npos) << message;
  EXPECT_EQ(CodeOf([&] { client.Import({"broken.bvh", broken}); }), grpc::StatusCode::INVALID_ARGUMENT);
  // Truncated, wrong channel counts, NaN.
  const std::string truncated(kArmBvh, std::string(kArmBvh).find("MOTION") + 20);
  EXPECT_EQ(CodeOf([&] { client.Import({"truncated.bvh", truncated}); }), grpc::StatusCode::INVALID_ARGUMENT);
  std::string short_frame = kArmBvh;
  short_frame.replace(short_frame.find("0 0 0 90 0 0 0 0 0"), 18, "0 0 0 90 0 0 0 0");
  message = MessageOf([&] { client.Import({"short.bvh", short_frame}); });
  EXPECT_NE(message.find("line 20"), std::string::npos) << message;
  std::string nan_value = kArmBvh;
  nan_value.replace(nan_value.find("0 0 0 90"), 8, "0 0 0 nan");
  EXPECT_EQ(CodeOf([&] { client.Import({"nan.bvh", nan_value}); }), grpc::StatusCode::INVALID_ARGUMENT);
  // Names that would escape the data dir.
  EXPECT_EQ(CodeOf([&] { client.Import({"arm.bvh", kArmBvh}, "../evil"); }), grpc::StatusCode::INVALID_ARGUMENT);
  // A taken name.
  EXPECT_EQ(CodeOf([&] { client.Import({"arm.bvh", kArmBvh}); }), grpc::StatusCode::ALREADY_EXISTS);
  // Over the upload limit (1 MiB here).
  std::string big = kArmBvh;
  while (big.size() < (3u << 20) / 2) big += "0 0 0 0 0 0 0 0 0\n";
  const grpc::Status too_big = StatusOf([&] { client.Import({"big.bvh", big}); });
  message = too_big.error_message();
  EXPECT_EQ(too_big.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(message.find("limit"), std::string::npos) << message;

  // Evaluate: NaN, negative and missing times, unknown clip and joint.
  auto evaluate = [&](std::vector<double> times, std::string clip = "arm", std::string joint = "") {
    v1::EvaluateClipRequest r;
    r.set_clip(clip);
    for (double t : times) r.add_times(t);
    if (!joint.empty()) r.add_joints(joint);
    return [&client, r] { client.EvaluateClip(r); };
  };
  EXPECT_EQ(CodeOf(evaluate({NAN})), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(MessageOf(evaluate({0.1, -1})).find("times[1]"), std::string::npos);
  EXPECT_EQ(CodeOf(evaluate({INFINITY})), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(CodeOf(evaluate({})), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(CodeOf(evaluate({0}, "nope")), grpc::StatusCode::NOT_FOUND);
  EXPECT_NE(MessageOf(evaluate({0}, "arm", "Elbow")).find("Elbow"), std::string::npos);
  // Streams validate too.
  v1::StreamClipRequest s;
  s.set_clip("arm");
  s.set_fps(-5);
  EXPECT_EQ(CodeOf([&] { client.StreamClip(s, [](const v1::PoseFrame&) { return true; }); }),
            grpc::StatusCode::INVALID_ARGUMENT);
  // FK with a bad pose.
  v1::ComputeFkRequest fk;
  fk.set_skeleton("arm");
  for (int i = 0; i < 4; ++i) fk.mutable_pose()->add_rotations(0);
  EXPECT_EQ(CodeOf([&] { client.ComputeFk(fk); }), grpc::StatusCode::INVALID_ARGUMENT);

  // Still serving, nothing stored changed.
  EXPECT_TRUE(client.Healthy());
  EXPECT_EQ(client.ListAssets().SerializeAsString(), before);
}

TEST_F(Foundation, ComputeFkOfAClientPose) {
  ServerProcess server(data_.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  client.Import({"arm.bvh", kArmBvh});
  v1::ComputeFkRequest fk;
  fk.set_skeleton("arm");
  // Root turned 90° about Z (w = cos 45°, z = sin 45°), child unrotated; root moved to (5,0,0).
  const float h = std::sqrt(0.5f);
  for (float v : {h, 0.f, 0.f, h, 1.f, 0.f, 0.f, 0.f}) fk.mutable_pose()->add_rotations(v);
  for (float v : {5.f, 0.f, 0.f}) fk.mutable_pose()->add_translations(v);
  const auto world = client.ComputeFk(fk);
  const auto& t = world.world().translations();
  ASSERT_EQ(t.size(), 6);
  EXPECT_NEAR(t[0], 5, 1e-5);
  EXPECT_NEAR(t[3], 5, 1e-5);
  EXPECT_NEAR(t[4], 2, 1e-5);
}

TEST_F(Foundation, SigtermEndsInFlightStreamsAndExitsZero) {
  ServerProcess server(data_.path(), {"--shutdown-grace", "1"});
  client::Client client(OptionsFor(server));
  std::atomic<int> frames{0};
  std::atomic<bool> ended{false};
  std::thread streamer([&] {
    v1::StreamClipRequest s;
    s.set_clip("demo_walk");
    s.set_loop(true);  // would run forever
    try {
      client.StreamClip(s, [&](const v1::PoseFrame&) {
        ++frames;
        return true;
      });
    } catch (const client::ClientError&) {}
    ended = true;
  });
  ASSERT_TRUE(WaitFor([&] { return frames >= 3; }, 30)) << "the stream did not start";
  EXPECT_EQ(server.Stop(SIGTERM, 10), 0) << ReadFile(server.log_file());
  streamer.join();
  EXPECT_TRUE(ended);
}

TEST_F(Foundation, InterruptedImportLeavesNoHalfAsset) {
  {
    ServerProcess server(data_.path(), {"--no-demo"});
    client::Client(OptionsFor(server)).Import({"arm.bvh", kArmBvh});
  }
  // What a crash between writes leaves: temporary files and a stored file no
  // manifest entry names, just written (a restart right after a kill -9).
  // Writers hold the data dir lock while writing, and the starting server
  // holds it now, so none of them can be an import in progress: all go at once.
  const fs::path leftovers[] = {data_.path() / "files" / ".half.bvh.tmp-1234",
                                data_.path() / "files" / "orphan.abc.bvh", data_.path() / ".manifest.json.tmp-99",
                                data_.path() / "files" / "killed.def.bvh"};
  for (const fs::path& p : leftovers) std::ofstream(p) << "HIERARCHY";
  ServerProcess server(data_.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  const auto assets = client.ListAssets();
  ASSERT_EQ(assets.assets_size(), 1);
  EXPECT_EQ(assets.assets(0).name(), "arm");
  for (const fs::path& p : leftovers) EXPECT_FALSE(fs::exists(p)) << p;
  EXPECT_EQ(client.GetClip("arm").frames(), 3);
}

// An asset whose stored file stops loading is skipped, not forgotten: a later
// import rewrites the manifest with its entry, so once the file is repaired
// the asset is back (and its file, a day old, is no leftover to remove).
TEST_F(Foundation, AnAssetThatDoesNotLoadSurvivesOtherWritesUntilRepaired) {
  {
    ServerProcess server(data_.path(), {"--no-demo"});
    client::Client client(OptionsFor(server));
    client.Import({"arm.bvh", kArmBvh});
    client.Import({"second.bvh", kArmBvh});
  }
  fs::path stored;
  for (const auto& entry : fs::directory_iterator(data_.path() / "files"))
    if (entry.path().filename().string().starts_with("arm.")) stored = entry.path();
  ASSERT_FALSE(stored.empty());
  std::ofstream(stored, std::ios::trunc) << "not a BVH";
  const auto a_day_ago = fs::file_time_type::clock::now() - std::chrono::hours(24);
  fs::last_write_time(stored, a_day_ago);
  {
    ServerProcess server(data_.path(), {"--no-demo"});
    client::Client client(OptionsFor(server));
    EXPECT_EQ(client.ListAssets().assets_size(), 1);  // "arm" is skipped
    client.Import({"third.bvh", kArmBvh});
    client.DeleteAsset("second");
  }
  std::ofstream(stored, std::ios::trunc) << kArmBvh;
  fs::last_write_time(stored, a_day_ago);
  ServerProcess server(data_.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  EXPECT_EQ(AssetNames(client), (std::set<std::string>{"arm", "third"}));
  EXPECT_TRUE(fs::exists(stored));
}

TEST_F(Foundation, CliCommandsAndErrors) {
  ServerProcess server(data_.path(), {"--no-demo"});
  const fs::path arm = WriteTemp(files_, "arm.bvh", kArmBvh);
  auto imported = RunCli(server.target(), {"import", arm.string(), "--name", "arm2"});
  ASSERT_EQ(imported.exit_code, 0) << imported.err;
  const json j = json::parse(imported.out);
  EXPECT_EQ(j["skeletons"][0]["name"], "arm2");
  EXPECT_EQ(j["clips"][0]["name"], "arm2");
  EXPECT_EQ(j["clips"][0]["skeleton"], "arm2");
  EXPECT_EQ(j["clips"][0]["frames"], 3);
  EXPECT_DOUBLE_EQ(j["clips"][0]["duration"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j["clips"][0]["frameTime"].get<double>(), 0.5);
  EXPECT_TRUE(j["meshes"].is_array());

  auto list = RunCli(server.target(), {"list", "--json"});
  ASSERT_EQ(list.exit_code, 0) << list.err;
  EXPECT_EQ(json::parse(list.out)["assets"][0]["name"], "arm2");

  auto pose = RunCli(server.target(), {"pose", "arm2", "--time", "0.5", "--json", "--space", "world"});
  ASSERT_EQ(pose.exit_code, 0) << pose.err;
  const json p = json::parse(pose.out);
  EXPECT_EQ(p["joints"][1]["name"], "Tip");
  EXPECT_EQ(p["joints"][1]["parent"], "Base");
  EXPECT_NEAR(p["joints"][1]["translation"][0].get<double>(), 1.0, kClipBound);
  EXPECT_NEAR(p["joints"][1]["translation"][1].get<double>(), 4.0, kClipBound);
  EXPECT_EQ(p["joints"][1]["rotation"].size(), 4u);

  auto stream = RunCli(server.target(), {"stream", "arm2", "--fps", "40", "--duration", "0.25"});
  ASSERT_EQ(stream.exit_code, 0) << stream.err;
  EXPECT_EQ(std::count(stream.out.begin(), stream.out.end(), '\n'), 10);

  const fs::path out = files_.path() / "out.bvh";
  auto exported = RunCli(server.target(), {"export", "arm2", "-o", out.string()});
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  EXPECT_NE(ReadFile(out).find("HIERARCHY"), std::string::npos);

  auto missing = RunCli(server.target(), {"pose", "nope", "--time", "0"});
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.err.find("NOT_FOUND"), std::string::npos) << missing.err;
  EXPECT_NE(missing.err.find("nope"), std::string::npos) << missing.err;

  auto deleted = RunCli(server.target(), {"delete", "arm2"});
  EXPECT_EQ(deleted.exit_code, 0) << deleted.err;
  auto unreachable = RunCli("127.0.0.1:1", {"--timeout", "2", "list"});
  EXPECT_NE(unreachable.exit_code, 0);
  EXPECT_NE(unreachable.err.find("UNAVAILABLE"), std::string::npos) << unreachable.err;
}

}  // namespace
}  // namespace armature::testing
