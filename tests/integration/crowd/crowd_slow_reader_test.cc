// A crowd client that stops reading is dropped once a frame has stayed
// unwritten for --crowd-write-timeout-seconds (1 s here, 10 s by default),
// while another crowd on the same server keeps its pace; the drop shows in
// the RPC metrics (CANCELLED) and in the server's log.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <string>

#include "armature/client.h"
#include "armature/v1/crowd.grpc.pb.h"
#include "support/client_helpers.h"
#include "support/metrics_scrape.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

constexpr char kCancelled[] =
    R"(armature_rpc_requests_total{method="armature.v1.CrowdService/CrowdSession",code="CANCELLED"})";

v1::CrowdCommand Start(double duration) {
  v1::CrowdCommand start;
  start.mutable_start()->set_fps(30);
  start.mutable_start()->set_duration(duration);
  return start;
}

v1::CrowdCommand Add(uint32_t id) {
  v1::CrowdCommand add;
  add.mutable_add()->set_id(id);
  add.mutable_add()->set_clip("demo_walk");
  add.mutable_add()->set_time_offset(0.01 * id);
  return add;
}

// A channel that takes little before it stops reading: no window growth.
std::shared_ptr<grpc::Channel> SmallWindowChannel(const ServerProcess& server) {
  grpc::ChannelArguments args;
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
  args.SetInt(GRPC_ARG_HTTP2_BDP_PROBE, 0);
  args.SetInt(GRPC_ARG_HTTP2_STREAM_LOOKAHEAD_BYTES, 16 << 10);
  return grpc::CreateCustomChannel(server.target(), grpc::InsecureChannelCredentials(), args);
}

TEST(CrowdSlowReader, IsDroppedAfterTheWriteTimeoutWhileOthersKeepPace) {
  TempDir data;
  ServerProcess server(data.path(), {"--crowd-write-timeout-seconds", "1"});
  const double cancelled_before = std::max(0.0, ScrapeSample(server, kCancelled));

  // The stalled crowd: 2,000 characters, about 100 kB a frame, never read.
  grpc::ClientContext stalled_context;
  auto stalled_stub = v1::CrowdService::NewStub(SmallWindowChannel(server));
  auto stalled = stalled_stub->CrowdSession(&stalled_context);
  ASSERT_TRUE(stalled->Write(Start(60)));
  for (uint32_t id = 0; id < 2000; ++id) ASSERT_TRUE(stalled->Write(Add(id)));
  stalled->WritesDone();

  // Meanwhile a reading crowd plays 3 s at its pace.
  client::Client reader_client(OptionsFor(server));
  auto reader_stub = v1::CrowdService::NewStub(reader_client.channel());
  grpc::ClientContext reader_context;
  const auto began = std::chrono::steady_clock::now();
  auto reader = reader_stub->CrowdSession(&reader_context);
  ASSERT_TRUE(reader->Write(Start(3)));
  for (uint32_t id = 0; id < 50; ++id) ASSERT_TRUE(reader->Write(Add(id)));
  reader->WritesDone();
  v1::CrowdFrame frame;
  size_t frames = 0, late = 0;
  while (reader->Read(&frame)) ++frames, late += frame.stats().late() ? 1 : 0;
  const double played = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  ASSERT_TRUE(reader->Finish().ok());
  // Every frame, on time overall; single ticks may be late (over half a tick) on a loaded machine.
  EXPECT_EQ(frames, 90u);  // 3 s at 30 fps
  EXPECT_LE(late, 30u);
  EXPECT_NEAR(played, 3.0, 0.5);

  // By now (3 s, the write timeout 1 s) the stalled crowd was dropped: reading what
  // was buffered ends in CANCELLED, well before its 60 s.
  const auto drained = std::chrono::steady_clock::now();
  size_t buffered = 0;
  while (stalled->Read(&frame)) ++buffered;
  const grpc::Status status = stalled->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::CANCELLED) << status.error_message();
  EXPECT_LT(buffered, 60u);  // frames that made it out before the writes blocked
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - drained).count(), 5.0);
  EXPECT_GE(ScrapeSample(server, kCancelled), cancelled_before + 1);
  std::ifstream log(server.log_file());
  std::stringstream text;
  text << log.rdbuf();
  EXPECT_NE(text.str().find("CrowdSession: a frame stayed unwritten 1 s (the client stopped reading)"),
            std::string::npos)
      << text.str();
  std::printf("reader: %zu frames in %.2f s, %zu late; stalled: %zu frames read after, then %s\n", frames, played, late,
              buffered, status.error_message().c_str());
}

}  // namespace
}  // namespace armature::testing
