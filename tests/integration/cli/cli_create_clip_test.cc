// `armature create-clip --skeleton S --keys FILE.json --name NAME --json`:
// FILE.json is the CreateClipRequest as proto3 JSON; it prints the new clip
// as `armature import` does. And the same request over REST.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {
using nlohmann::json;

class CliCreateClip : public ::testing::Test {
 protected:
  CommandResult Cli(const std::vector<std::string>& args) {
    std::string line = ShellQuote(ARMATURE_CLI_BIN) + " --server " + ShellQuote(server_.target()) + " --json";
    for (const auto& a : args) line += " " + ShellQuote(a);
    return RunCommand(line);
  }
  TempDir data_, files_;
  ServerProcess server_{data_.path()};
};

// The issue's example, verbatim in shape: rotations 4 per key, translations 3 per key.
const char kKeys[] = R"({"tracks":[{"joint":"Head","times":[0,0.5],
  "rotations":[1,0,0,0, 0.7071067811865476,0,0.7071067811865476,0],
  "translations":[0,0.1,0, 0,0.3,0],"interpolation":"LINEAR"}]})";

TEST_F(CliCreateClip, ACubicClipReportsCubic) {
  const std::string file = WriteTemp(files_, "cubic.json", R"({"tracks":[{"joint":"Head","times":[0,0.5,1],
    "euler":[0,0,0, 25,0,0, 0,0,0],"interpolation":"CUBIC"}]})")
                               .string();
  const CommandResult r = Cli({"create-clip", "--skeleton", "demo_walk", "--keys", file, "--name", "nod"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json out = json::parse(r.out);
  EXPECT_EQ(out["clip"]["interpolation"], "CUBIC") << out["clip"].dump();  // was LINEAR
  const CommandResult linear = Cli({"create-clip", "--skeleton", "demo_walk", "--keys",
                                    WriteTemp(files_, "linear.json", kKeys).string(), "--name", "slide"});
  ASSERT_EQ(linear.exit_code, 0) << linear.err;
  EXPECT_EQ(json::parse(linear.out)["clip"]["interpolation"], "LINEAR");
}

TEST_F(CliCreateClip, KeysFileMakesAClipPrintedAsImportDoes) {
  const std::string file = WriteTemp(files_, "nod.json", kKeys).string();
  const CommandResult r = Cli({"create-clip", "--skeleton", "demo_walk", "--keys", file, "--name", "nod"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json out = json::parse(r.out);
  EXPECT_EQ(out["asset"], "nod");
  ASSERT_EQ(out["clips"].size(), 1u) << out.dump();
  EXPECT_EQ(out["clips"][0]["name"], "nod");
  EXPECT_DOUBLE_EQ(out["clips"][0]["duration"].get<double>(), 0.5);
  EXPECT_EQ(out["clips"][0]["frames"], 2);
  // The clip is demo_walk's own: the name given is the name to call, and no copy of the skeleton is listed.
  EXPECT_EQ(out["clips"][0]["skeleton"], "demo_walk");
  EXPECT_EQ(out["skeletons"].size(), 0u);
  EXPECT_EQ(out["clip"]["joints"].size(), 19u);

  // Halfway: 45° about Y, the translation halfway (local space).
  const CommandResult pose = Cli({"pose", "nod", "--time", "0.25", "--space", "local", "--joints", "Head"});
  ASSERT_EQ(pose.exit_code, 0) << pose.err;
  const json p = json::parse(pose.out);
  const json& head = p["joints"][0];
  EXPECT_NEAR(head["rotation"][0].get<double>(), std::cos(M_PI / 8), 1e-6) << p.dump();
  EXPECT_NEAR(head["rotation"][2].get<double>(), std::sin(M_PI / 8), 1e-6) << p.dump();
  EXPECT_NEAR(head["translation"][1].get<double>(), 0.2, 1e-6) << p.dump();

  // Again without --replace: ALREADY_EXISTS; with --merge the file's Head replaces the stored one.
  const CommandResult again = Cli({"create-clip", "--skeleton", "demo_walk", "--keys", file, "--name", "nod"});
  EXPECT_NE(again.exit_code, 0);
  EXPECT_NE(again.err.find("ALREADY_EXISTS"), std::string::npos) << again.err;
  const std::string later =
      WriteTemp(files_, "later.json", R"({"tracks":[{"joint":"Head","times":[0,2],"rotations":[1,0,0,0,1,0,0,0]}]})")
          .string();
  const CommandResult merged = Cli({"create-clip", "--keys", later, "--name", "nod", "--merge"});
  ASSERT_EQ(merged.exit_code, 0) << merged.err;
  EXPECT_DOUBLE_EQ(json::parse(merged.out)["clip"]["duration"].get<double>(), 2.0);
}

TEST_F(CliCreateClip, BadKeysFilesExitNonZeroNamingTheProblem) {
  const std::string not_json = WriteTemp(files_, "bad.json", "{\"tracks\": [").string();
  const CommandResult a = Cli({"create-clip", "--skeleton", "demo_walk", "--keys", not_json, "--name", "x"});
  EXPECT_NE(a.exit_code, 0);
  EXPECT_NE(a.err.find("bad.json"), std::string::npos) << a.err;
  const std::string unsorted =
      WriteTemp(files_, "unsorted.json",
                R"({"tracks":[{"joint":"Head","times":[0.5,0],"rotations":[1,0,0,0,1,0,0,0]}]})")
          .string();
  const CommandResult b = Cli({"create-clip", "--skeleton", "demo_walk", "--keys", unsorted, "--name", "x"});
  EXPECT_NE(b.exit_code, 0);
  EXPECT_NE(b.err.find("INVALID_ARGUMENT"), std::string::npos) << b.err;
  EXPECT_NE(b.err.find("joint 'Head'"), std::string::npos) << b.err;
  EXPECT_NE(b.err.find("key 1"), std::string::npos) << b.err;
}

TEST_F(CliCreateClip, RestRouteTakesTheSameJson) {
  json request = json::parse(kKeys);
  request["name"] = "viarest";
  const std::string body = WriteTemp(files_, "rest.json", request.dump()).string();
  const std::string url =
      "http://127.0.0.1:" + std::to_string(server_.http_port()) + "/v1/skeletons/demo_walk:createClip";
  const CommandResult r = RunCommand("curl -s -X POST -H 'Content-Type: application/json' --data-binary @" +
                                     ShellQuote(body) + " " + ShellQuote(url));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json out = json::parse(r.out);
  EXPECT_EQ(out["clip"]["name"], "viarest") << r.out;
  EXPECT_EQ(out["asset"]["name"], "viarest") << r.out;
  const CommandResult bad = RunCommand(
      "curl -s -o /dev/null -w '%{http_code}' -X POST -H 'Content-Type: "
      "application/json' -d '{\"name\":\"b\",\"tracks\":[{\"joint\":\"Nope\",\"times\":[0],"
      "\"rotations\":[1,0,0,0]}]}' " +
      ShellQuote(url));
  EXPECT_EQ(bad.out, "400");
}

}  // namespace
}  // namespace armature::testing
