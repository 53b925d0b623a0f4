// `armature play`: a PlaybackSession from the command line; one JSON line per
// frame with the playing motions, the crossfade ramping their weights, the
// next clip from the frame at --at exactly.
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

std::vector<json> FrameLines(const std::string& out) {
  std::vector<json> frames;
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);)
    if (!line.empty()) frames.push_back(json::parse(line));
  return frames;
}

TEST(CliPlay, CrossfadesToTheNextClipAndPrintsTheWeights) {
  TempDir data;
  ServerProcess server(data.path());
  const CommandResult r =
      RunCli(server.target(), {"play", "demo_walk", "demo_walk", "--then", "demo_walk", "--at", "0.1", "--crossfade",
                               "0.2", "--fps", "30", "--duration", "0.6", "--joints", "Hips", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<json> frames = FrameLines(r.out);
  ASSERT_EQ(frames.size(), 18u) << r.out;  // 0.6 s at 30 fps
  size_t fade = 0;
  while (fade < frames.size() && frames[fade]["motions"].size() < 2) ++fade;
  ASSERT_LT(fade, frames.size() - 6) << "the crossfade never started: " << r.out;
  EXPECT_GE(frames[fade]["time"].get<double>(), 0.1 - 1e-9) << "sent when the frame at --at arrived";
  for (size_t k = 0; k < 6; ++k) {  // 0.2 s: 6 frames, weights (1 − a, a) with a = k/6
    const json& m = frames[fade + k]["motions"];
    ASSERT_EQ(m.size(), 2u) << k;
    EXPECT_NEAR(m[1]["weight"].get<double>(), k / 6.0, 1e-9) << k;
    EXPECT_NEAR(m[0]["weight"].get<double>(), 1 - k / 6.0, 1e-9) << k;
  }
  if (fade + 6 < frames.size()) EXPECT_EQ(frames[fade + 6]["motions"].size(), 1u);
  EXPECT_EQ(frames[0]["joints"][0]["name"], "Hips");
}

TEST(CliPlay, TheNextClipShowsFirstAtTheFrameOfAt) {
  TempDir data;
  ServerProcess server(data.path());
  const CommandResult r =
      RunCli(server.target(), {"play", "demo_walk", "demo_walk", "--then", "demo_walk", "--at", "0.5", "--fps", "30",
                               "--duration", "0.8", "--joints", "Hips", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<json> frames = FrameLines(r.out);
  ASSERT_EQ(frames.size(), 24u) << r.out;  // 0.8 s at 30 fps
  size_t first = 0;
  while (first < frames.size() && frames[first]["motions"].size() < 2) ++first;
  ASSERT_LT(first, frames.size()) << "the next clip never played: " << r.out;
  EXPECT_EQ(first, 15u) << "frame 15 (t = 0.5) is the first with the next clip";
  EXPECT_NEAR(frames[first]["time"].get<double>(), 0.5, 1e-9);
  EXPECT_EQ(frames[first]["motions"][1]["id"], 1);
  EXPECT_EQ(frames[first]["motions"][1]["weight"].get<double>(), 0);
}

}  // namespace
}  // namespace armature::testing
