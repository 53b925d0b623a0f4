// --max-streams-per-client: a client holds at most that many streams open
// (StreamClip here); one more is refused naming the flag, and closing one
// makes room again.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "armature/v1/poses.grpc.pb.h"
#include "support/client_helpers.h"
#include "engine/testing/test_files.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

// One open StreamClip call (looping, so it lasts until cancelled).
struct OpenStream {
  grpc::ClientContext context;
  std::unique_ptr<grpc::ClientReader<v1::PoseFrame>> reader;
  v1::PoseFrame first;
  bool got_first = false;

  OpenStream(v1::PoseService::Stub& stub, const std::string& clip) {
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
    v1::StreamClipRequest r;
    r.set_clip(clip);
    r.set_fps(10);
    r.set_loop(true);
    reader = stub.StreamClip(&context, r);
    got_first = reader->Read(&first);
  }
  // Ends the call: cancels it unless it already failed, and returns its status.
  grpc::Status Close() {
    if (got_first) context.TryCancel();
    v1::PoseFrame rest;
    while (reader->Read(&rest)) {}
    return reader->Finish();
  }
};

TEST(StreamLimits, OneStreamOverTheLimitIsRefusedUntilOneCloses) {
  constexpr int kLimit = 3;
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-streams-per-client", std::to_string(kLimit)});
  client::Client client(OptionsFor(server));
  client.Import({"arm.bvh", kArmBvh});
  auto stub = v1::PoseService::NewStub(client.channel());

  std::vector<std::unique_ptr<OpenStream>> open;
  for (int i = 0; i < kLimit; ++i) {
    open.push_back(std::make_unique<OpenStream>(*stub, "arm"));
    ASSERT_TRUE(open.back()->got_first) << "stream " << i
                                        << " within the limit: " << open.back()->Close().error_message();
  }
  OpenStream over(*stub, "arm");
  EXPECT_FALSE(over.got_first);
  const grpc::Status refused = over.Close();
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << refused.error_message();
  EXPECT_NE(refused.error_message().find("--max-streams-per-client"), std::string::npos) << refused.error_message();
  EXPECT_NE(refused.error_message().find("StreamClip"), std::string::npos) << refused.error_message();
  // Unary calls are not streams: still served.
  EXPECT_TRUE(client.Healthy());

  // Close one: the server gives its place back when the call is done, which
  // may come a moment after the client's cancel, so retry until admitted.
  EXPECT_EQ(open.front()->Close().error_code(), grpc::StatusCode::CANCELLED);
  open.erase(open.begin());
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  std::unique_ptr<OpenStream> again;
  grpc::Status last;
  while (std::chrono::steady_clock::now() < until) {
    again = std::make_unique<OpenStream>(*stub, "arm");
    if (again->got_first) break;
    last = again->Close();
    ASSERT_EQ(last.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << last.error_message();
    again.reset();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(again) << "no stream admitted within 20 s of closing one: " << last.error_message();
  EXPECT_EQ(again->first.index(), 0u);
  EXPECT_EQ(again->Close().error_code(), grpc::StatusCode::CANCELLED);
  for (auto& s : open) EXPECT_EQ(s->Close().error_code(), grpc::StatusCode::CANCELLED);
}

// What curl prints for a REST stream opened from `source` (a loopback
// address), cut off after `seconds`.
std::string CurlStream(const std::string& source, const std::string& url, int seconds) {
  const std::string command =
      "curl -sN --interface " + source + " --max-time " + std::to_string(seconds) + " '" + url + "' 2>/dev/null";
  std::string out;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char buffer[4096];
    size_t n;
    while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0 && out.size() < (1 << 20)) out.append(buffer, n);
    pclose(pipe);
  }
  return out;
}

// REST clients reach gRPC through the gateway's in-process channel; each HTTP
// client counts apart (by address), not all of them as one.
TEST(StreamLimits, RestClientsCountApartByAddress) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-streams-per-client", "1"});
  client::Client client(OptionsFor(server));
  client.Import({"arm.bvh", kArmBvh});
  const std::string url =
      "http://127.0.0.1:" + std::to_string(server.http_port()) + "/v1/clips/arm:stream?loop=true&fps=10";

  // The first client's stream: held in the background until it has its
  // place (its first frame has arrived).
  const std::string held = (data.path() / "held.txt").string();
  ASSERT_EQ(
      std::system(("curl -sN --interface 127.0.0.1 --max-time 8 '" + url + "' > " + held + " 2>/dev/null &").c_str()),
      0);
  std::string first;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(6);
  while (first.find("data: ") == std::string::npos && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    first = test_util::ReadFileBytes(held).value_or("");
  }
  ASSERT_NE(first.find("data: "), std::string::npos) << "the first REST stream got no frame: " << first;
  const std::string same = CurlStream("127.0.0.1", url, 1);
  const std::string other = CurlStream("127.0.0.2", url, 1);
  EXPECT_NE(same.find("--max-streams-per-client"), std::string::npos) << "a second stream from 127.0.0.1: " << same;
  EXPECT_NE(other.find("data: "), std::string::npos) << "a stream from 127.0.0.2: " << other;
  EXPECT_EQ(other.find("--max-streams-per-client"), std::string::npos) << other;
}

}  // namespace
}  // namespace armature::testing
