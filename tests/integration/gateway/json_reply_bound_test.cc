// REST answers are bounded in their JSON form (issue 27, section 1). A JSON
// answer over --max-message-mb is refused before the work, naming the limit,
// its estimated size and the binary or streaming alternative, while the same
// request for the binary encoding is answered. Writing a large answer as JSON
// costs the server at most three times its size in memory (with protobuf's
// printer: 1.39 GB of peak RSS for a 24 MB answer).
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "armature/v1/poses.pb.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {
using nlohmann::json;

httplib::Client Http(const ServerProcess& server) {
  httplib::Client http("127.0.0.1", server.http_port());
  http.set_read_timeout(120);
  http.set_write_timeout(60);
  return http;
}

std::string EvaluateBody(int times) {
  std::string body = "{\"times\":[";
  for (int i = 0; i < times; ++i) body += (i ? "," : "") + std::to_string(i % 1000 / 30.0);
  return body + "]}";
}

size_t JointsOfDemoWalk(httplib::Client& http) {
  const auto clip = http.Get("/v1/clips/demo_walk");
  EXPECT_TRUE(clip && clip->status == 200);
  return clip ? json::parse(clip->body)["joints"].size() : 0;
}

TEST(JsonReplyBound, AJsonAnswerOverTheLimitIsRefusedBeforeTheWorkAndTheBinaryOneIsAnswered) {
  TempDir data;
  ServerProcess server(data.path(), {"--max-message-mb", "1"});
  auto http = Http(server);
  const size_t joints = JointsOfDemoWalk(http);
  ASSERT_GT(joints, 0u);
  // About 0.9 MiB as protobuf (28 bytes a joint and 16 a pose), about 1.5 times that as JSON.
  const int times = static_cast<int>(0.9 * (1 << 20) / (28.0 * joints + 16));
  const std::string body = EvaluateBody(times);

  const auto refused = http.Post("/v1/clips/demo_walk:evaluate", body, "application/json");
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 429) << refused->body.substr(0, 300);
  const json error = json::parse(refused->body, nullptr, false);
  ASSERT_TRUE(error.is_object()) << refused->body.substr(0, 300);
  EXPECT_EQ(error.value("code", 0), 8) << "RESOURCE_EXHAUSTED";
  const std::string message = error.value("message", "");
  for (const std::string& fragment : std::vector<std::string>{
           "EvaluateClip: the answer would take about ", " MiB as JSON (" + std::to_string(times) + " times x ",
           "over the message limit of 1.0 MiB (--max-message-mb)", "Accept: application/x-protobuf", "StreamClip"})
    EXPECT_NE(message.find(fragment), std::string::npos) << fragment << " not in: " << message;

  const auto binary =
      http.Post("/v1/clips/demo_walk:evaluate", {{"Accept", "application/x-protobuf"}}, body, "application/json");
  ASSERT_TRUE(binary);
  ASSERT_EQ(binary->status, 200) << binary->body.substr(0, 300);
  v1::EvaluateClipResponse response;
  ASSERT_TRUE(response.ParseFromString(binary->body));
  EXPECT_EQ(response.poses_size(), times);
  EXPECT_LT(binary->body.size(), size_t{1} << 20);

  // A tenth of it fits as JSON too.
  const auto small = http.Post("/v1/clips/demo_walk:evaluate", EvaluateBody(times / 10), "application/json");
  ASSERT_TRUE(small);
  EXPECT_EQ(small->status, 200) << small->body.substr(0, 300);
}

// The process's resident memory: VmRSS or VmHWM (its peak) in bytes.
double ProcessBytes(pid_t pid, const std::string& key) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind(key + ":", 0) == 0) return std::stod(line.substr(key.size() + 1)) * 1024;
  return -1;
}

struct Measured {
  size_t answer_bytes = 0;
  double growth_bytes = 0;  // of the server's peak resident memory while answering
};

// EvaluateClip of 30,000 times on a fresh server, as JSON or as protobuf.
Measured Evaluate30k(const std::vector<std::pair<std::string, std::string>>& headers) {
  TempDir data;
  ServerProcess server(data.path());
  auto http = Http(server);
  httplib::Headers h(headers.begin(), headers.end());
  // Warm up: the handler's and gateway's threads and pools exist before the measurement.
  EXPECT_EQ(http.Post("/v1/clips/demo_walk:evaluate", h, EvaluateBody(100), "application/json")->status, 200);
  // "5" resets the peak (VmHWM) to the current resident size.
  std::ofstream(std::string("/proc/") + std::to_string(server.pid()) + "/clear_refs") << "5";
  const double before = ProcessBytes(server.pid(), "VmRSS");
  const auto answer = http.Post("/v1/clips/demo_walk:evaluate", h, EvaluateBody(30000), "application/json");
  const double peak = ProcessBytes(server.pid(), "VmHWM");
  EXPECT_TRUE(answer && answer->status == 200);
  EXPECT_GT(before, 0);
  return {answer ? answer->body.size() : 0, peak - before};
}

// The answer itself (the handler's message and its encoding) costs the same
// in either encoding; writing it as JSON may cost three times the JSON's
// size on top (it cost 1.29 GB, 54 times, with protobuf's printer).
TEST(JsonReplyBound, AJsonAnswerCostsAtMostThreeTimesItsSizeMoreMemoryThanTheBinaryOne) {
  const Measured json_answer = Evaluate30k({});
  const Measured binary_answer = Evaluate30k({{"Accept", "application/x-protobuf"}});
  EXPECT_GT(json_answer.answer_bytes, 15e6) << "the premise: a large answer";
  const double extra = json_answer.growth_bytes - binary_answer.growth_bytes;
  EXPECT_LE(extra, 3.0 * static_cast<double>(json_answer.answer_bytes))
      << "peak RSS grew by " << json_answer.growth_bytes / 1e6 << " MB for " << json_answer.answer_bytes / 1e6
      << " MB of JSON, by " << binary_answer.growth_bytes / 1e6 << " MB for " << binary_answer.answer_bytes / 1e6
      << " MB of protobuf";
}

}  // namespace
}  // namespace armature::testing
