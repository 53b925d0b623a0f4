// The CLI's global options (--server, --token, --timeout, --json) before or
// after the subcommand, and the build info both binaries and /metrics report.
#include <regex>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "armature/build_info.h"
#include "support/client_helpers.h"
#include "support/metrics_scrape.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {
using nlohmann::json;

// The CLI with exactly these arguments (RunCli puts --server first).
CommandResult Cli(const std::vector<std::string>& args) {
  std::string line = ShellQuote(ARMATURE_CLI_BIN);
  for (const auto& a : args) line += " " + ShellQuote(a);
  return RunCommand(line);
}

class CliFlags : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto arm = WriteTemp(files_, "arm.bvh", kArmBvh);
    ASSERT_EQ(Cli({"--server", server_.target(), "import", arm.string()}).exit_code, 0);
  }
  TempDir data_, files_;
  ServerProcess server_{data_.path(), {"--no-demo"}};
};

TEST_F(CliFlags, GlobalOptionsGoBeforeOrAfterTheSubcommand) {
  const std::string target = server_.target();
  // Before, after, and around the subcommand's own arguments: the same answer.
  for (const auto& args :
       std::vector<std::vector<std::string>>{{"--server", target, "--json", "--timeout", "5", "list"},
                                             {"list", "--server", target, "--json", "--timeout", "5"},
                                             {"--json", "list", "--server", target},
                                             {"list", "--timeout", "5", "--json", "--server=" + target}}) {
    const CommandResult r = Cli(args);
    ASSERT_EQ(r.exit_code, 0) << args[0] << " " << args[1] << ": " << r.err;
    EXPECT_EQ(json::parse(r.out)["assets"][0]["name"], "arm") << r.out;
  }
  // After a positional argument and a subcommand option.
  const CommandResult pose = Cli({"pose", "arm", "--time", "0.5", "--server", target, "--json"});
  ASSERT_EQ(pose.exit_code, 0) << pose.err;
  const json p = json::parse(pose.out);
  EXPECT_EQ(p["joints"][1]["name"], "Tip");
  // The tip: the root (1,2,3) plus 2 along X turned 90° about Z at 0.5 s.
  EXPECT_NEAR(p["joints"][1]["translation"][1].get<double>(), 4.0, 1e-5);
  // Without --json the same command prints the table.
  const CommandResult table = Cli({"pose", "arm", "--time", "0.5", "--server", target});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("clip arm at 0.500000 s (world space)"), std::string::npos) << table.out;
  // --timeout after the subcommand is the global option: its check applies.
  const CommandResult bad_timeout = Cli({"list", "--server", target, "--timeout", "-1"});
  EXPECT_NE(bad_timeout.exit_code, 0);
  EXPECT_NE(bad_timeout.err.find("--timeout"), std::string::npos) << bad_timeout.err;
  // An option no command knows is still refused, naming it.
  const CommandResult unknown = Cli({"list", "--server", target, "--no-such-flag"});
  EXPECT_NE(unknown.exit_code, 0);
  EXPECT_NE(unknown.err.find("--no-such-flag"), std::string::npos) << unknown.err;
}

TEST_F(CliFlags, JsonOnEveryCommand) {
  const std::string target = server_.target();
  const CommandResult health = Cli({"health", "--server", target, "--json"});
  ASSERT_EQ(health.exit_code, 0) << health.err;
  EXPECT_EQ(json::parse(health.out)["status"], "SERVING");
  const CommandResult deleted = Cli({"--json", "delete", "arm", "--server", target});
  ASSERT_EQ(deleted.exit_code, 0) << deleted.err;
  EXPECT_EQ(json::parse(deleted.out)["name"], "arm");
  EXPECT_EQ(json::parse(Cli({"list", "--json", "--server", target}).out)["assets"].size(), 0u);
}

TEST(CliToken, TokenAfterTheSubcommandIsSent) {
  TempDir data, files;
  const auto tokens = WriteTemp(files, "tokens", "tok-123\n");
  ServerProcess server(data.path(), {"--auth-token-file", tokens.string()});
  const CommandResult with = Cli({"list", "--server", server.target(), "--token", "tok-123", "--json"});
  ASSERT_EQ(with.exit_code, 0) << with.err;
  EXPECT_EQ(json::parse(with.out)["assets"].size(), 2u);  // the seeded demo assets
  const CommandResult without = Cli({"list", "--server", server.target()});
  EXPECT_NE(without.exit_code, 0);
  EXPECT_NE(without.err.find("UNAUTHENTICATED"), std::string::npos) << without.err;
}

TEST(BuildInfo, VersionOnBothBinariesAndInMetrics) {
  // What the header holds: the CMake project version and a git commit (or "unknown").
  EXPECT_TRUE(std::regex_match(build_info::kVersion, std::regex(R"(\d+\.\d+\.\d+)"))) << build_info::kVersion;
  EXPECT_TRUE(std::regex_match(build_info::kCommit, std::regex("[0-9a-f]{12}|unknown"))) << build_info::kCommit;
  const std::string suffix = std::string(" ") + build_info::kVersion + " (commit " + build_info::kCommit + ")\n";

  const CommandResult cli = Cli({"--version"});
  EXPECT_EQ(cli.exit_code, 0) << cli.err;
  EXPECT_EQ(cli.out, "armature" + suffix);
  const CommandResult server_version = RunCommand(ShellQuote(ARMATURE_SERVER_BIN) + " --version");
  EXPECT_EQ(server_version.exit_code, 0) << server_version.err;
  EXPECT_EQ(server_version.out, "armature-server" + suffix);

  TempDir data;
  ServerProcess server(data.path(), {"--no-demo"});
  const std::string sample = std::string("armature_build_info{version=\"") + build_info::kVersion + "\",commit=\"" +
                             build_info::kCommit + "\"}";
  EXPECT_EQ(ScrapeSample(server, sample), 1);
}

}  // namespace
}  // namespace armature::testing
