// Messages a user can act on: a mistyped command or option gets "did you
// mean", enums take any case, bounds are readable, an existing asset names
// --replace, and an unreachable server is named with how to start one.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

// A two-joint arm with an exporter's namespace on every joint, as Mixamo writes them.
constexpr char kMixamoArmBvh[] = R"(HIERARCHY
ROOT mixamorig:Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT mixamorig:LeftArm
  {
    OFFSET 0 1 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT mixamorig:LeftHand
    {
      OFFSET 1 0 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      End Site
      {
        OFFSET 1 0 0
      }
    }
  }
}
MOTION
Frames: 1
Frame Time: 0.5
0 0 0 0 0 0 0 0 0 0 0 0
)";

class CliMessages : public ::testing::Test {
 protected:
  TempDir data_, files_;
  ServerProcess server_{data_.path()};
};

TEST_F(CliMessages, AMistypedCommandSuggestsTheCommand) {
  const CommandResult r = RunCli(server_.target(), {"psoe", "demo_walk", "--time", "0.5"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("unknown command 'psoe'; did you mean 'pose'?"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("A subcommand is required"), std::string::npos) << r.err;
}

TEST_F(CliMessages, AMistypedOptionSuggestsTheOption) {
  const CommandResult r = RunCli(server_.target(), {"pose", "demo_walk", "--tme", "0.5"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("pose: unknown option '--tme'; did you mean '--time'?"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("is required"), std::string::npos) << r.err;
}

TEST_F(CliMessages, EnumsTakeAnyCase) {
  const CommandResult upper = RunCli(server_.target(), {"pose", "demo_walk", "--time", "0.5", "--space", "World",
                                                        "--interpolation", "CUBIC", "--json"});
  ASSERT_EQ(upper.exit_code, 0) << upper.err;
  const CommandResult lower = RunCli(server_.target(), {"pose", "demo_walk", "--time", "0.5", "--space", "world",
                                                        "--interpolation", "cubic", "--json"});
  ASSERT_EQ(lower.exit_code, 0) << lower.err;
  EXPECT_EQ(nlohmann::json::parse(upper.out), nlohmann::json::parse(lower.out));
  EXPECT_EQ(nlohmann::json::parse(upper.out)["space"], "world");
}

TEST_F(CliMessages, ABoundIsPrintedShort) {
  const CommandResult r = RunCli(server_.target(), {"stream", "demo_walk", "--fps", "0"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--fps: must be greater than 0, got 0"), std::string::npos) << r.err;
  EXPECT_LT(r.err.size(), 200u) << r.err;  // was "not in range 0.000000 to 179769313486231570…" (300 digits)
}

TEST_F(CliMessages, AnExistingAssetNamesTheReplaceFlag) {
  const auto arm = WriteTemp(files_, "arm.bvh", kArmBvh);
  ASSERT_EQ(RunCli(server_.target(), {"import", arm.string()}).exit_code, 0);
  const CommandResult again = RunCli(server_.target(), {"import", arm.string()});
  EXPECT_NE(again.exit_code, 0);
  EXPECT_NE(again.err.find("asset 'arm' already exists (add --replace to overwrite it)"), std::string::npos)
      << again.err;
  EXPECT_EQ(again.err.find("set replace"), std::string::npos) << again.err;
}

TEST_F(CliMessages, AnIkJointWithoutItsNamespaceSuggestsIt) {
  const auto arm = WriteTemp(files_, "mixamo_arm.bvh", kMixamoArmBvh);
  const CommandResult imported = RunCli(server_.target(), {"import", arm.string()});
  ASSERT_EQ(imported.exit_code, 0) << imported.err;
  const CommandResult r = RunCli(server_.target(), {"ik", "mixamo_arm", "-e", "LeftHand=1,1.5,0"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("unknown joint 'LeftHand'; did you mean 'mixamorig:LeftHand'?"), std::string::npos) << r.err;
}

TEST(CliNoServer, NamesTheAddressAndHowToStartOne) {
  const CommandResult r = RunCli("127.0.0.1:1", {"list"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("no armature-server answers at 127.0.0.1:1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("make run"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--server HOST:PORT"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace armature::testing
