// `armature stream --motion FILE.json` and `armature skin MESH --motion
// FILE.json`: the same JSON as with a clip, on the demo character.
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {
using nlohmann::json;

class CliMotion : public ::testing::Test {
 protected:
  CommandResult Cli(const std::vector<std::string>& args) {
    std::string line = ShellQuote(ARMATURE_CLI_BIN) + " --server " + ShellQuote(server_.target()) + " --json";
    for (const auto& a : args) line += " " + ShellQuote(a);
    return RunCommand(line);
  }
  std::string MotionFile(const std::string& name, const json& motion) {
    return WriteTemp(files_, name, motion.dump()).string();
  }
  TempDir data_, files_;
  ServerProcess server_{data_.path()};
};

TEST_F(CliMotion, SkinWithAOneLayerMotionPrintsWhatTheClipDoes) {
  const std::string file = MotionFile("walk.json", {{"layers", {{{"clip", "demo_character.walk"}}}}});
  const CommandResult by_motion = Cli({"skin", "demo_character.body", "--motion", file, "--time", "0.7"});
  ASSERT_EQ(by_motion.exit_code, 0) << by_motion.err;
  const CommandResult by_clip =
      Cli({"skin", "demo_character.body", "--clip", "demo_character.walk", "--time", "0.7", "--loop"});
  ASSERT_EQ(by_clip.exit_code, 0) << by_clip.err;
  const json a = json::parse(by_motion.out), b = json::parse(by_clip.out);
  EXPECT_EQ(a["mesh"], "demo_character.body");
  EXPECT_EQ(a["vertexCount"], b["vertexCount"]);
  ASSERT_EQ(a["positions"].size(), b["positions"].size());
  for (size_t i = 0; i < a["positions"].size(); ++i)
    ASSERT_NEAR(a["positions"][i].get<double>(), b["positions"][i].get<double>(), 1e-3) << i;
  // Exactly one of --clip and --motion.
  EXPECT_NE(Cli({"skin", "demo_character.body", "--time", "0.7"}).exit_code, 0);
  EXPECT_NE(Cli({"skin", "demo_character.body", "--clip", "demo_walk", "--motion", file, "--time", "0.7"}).exit_code,
            0);
}

// One JSON line per frame, as `stream CLIP`, each the pose `pose --motion`
// gives at the frame's time; EXTRACT adds the root's delta since the previous frame.
TEST_F(CliMotion, StreamAMotionPrintsFramesAsPoseDoes) {
  const std::string file =
      MotionFile("extract.json",
                 {{"layers", {{{"clip", "demo_walk"}}, {{"clip", "demo_walk"}, {"timeOffset", 0.5}, {"weight", 0.5}}}},
                  {"rootMotion", "EXTRACT"}});
  const CommandResult r = Cli({"stream", "--motion", file, "--fps", "60", "--duration", "0.1", "--speed", "5"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream lines(r.out);
  std::vector<json> frames;
  for (std::string line; std::getline(lines, line);) frames.push_back(json::parse(line));
  ASSERT_GE(frames.size(), 5u);
  double z = 0;
  for (const json& f : frames) {
    ASSERT_TRUE(f.contains("rootDelta")) << f.dump();
    z += f["rootDelta"]["translation"][2].get<double>();
    EXPECT_EQ(f["joints"].size(), 19u);
  }
  EXPECT_GT(z, 0);  // the walk moves along +Z
  const json& last = frames.back();
  std::ostringstream time;
  time.precision(17);
  time << last["time"].get<double>();
  const CommandResult pose = Cli({"pose", "--motion", file, "--time", time.str()});
  ASSERT_EQ(pose.exit_code, 0) << pose.err;
  const json p = json::parse(pose.out);
  for (size_t j = 0; j < 19; ++j)
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(p["joints"][j]["translation"][i].get<double>(), last["joints"][j]["translation"][i].get<double>(),
                  1e-3)
          << j << " " << i;
  EXPECT_NE(Cli({"stream", "demo_walk", "--motion", file}).exit_code, 0);
}

}  // namespace
}  // namespace armature::testing
