// SIGTERM with calls in flight: they keep being served during
// --shutdown-grace, are cancelled after it, and the process exits 0 within
// the grace plus a margin (a watchdog ends it 3 s past the grace even when a
// handler is stuck).
#include <signal.h>

#include <atomic>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "armature/v1/assets.grpc.pb.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

TEST(Shutdown, CallsInFlightAreCancelledAfterTheGraceAndTheProcessExitsZero) {
  constexpr double kGrace = 2;
  TempDir data;
  ServerProcess server(data.path(), {"--shutdown-grace", "2"});
  client::Client client(OptionsFor(server));

  // A stream that would run forever.
  std::atomic<int> frames{0};
  std::atomic<int> frames_at_term{-1};
  grpc::StatusCode stream_end = grpc::StatusCode::OK;
  std::thread streamer([&] {
    v1::StreamClipRequest s;
    s.set_clip("demo_walk");
    s.set_loop(true);
    stream_end = CodeOf([&] { client.StreamClip(s, [&](const v1::PoseFrame&) { return ++frames, true; }); });
  });
  // An upload the client never finishes: the handler waits on the client.
  auto stub = v1::AssetService::NewStub(client.channel());
  grpc::ClientContext upload_context;
  v1::ImportAssetResponse upload_response;
  auto upload = stub->ImportAsset(&upload_context, &upload_response);
  v1::ImportAssetRequest first;
  first.set_filename("half.bvh");
  first.set_data(std::string(kArmBvh).substr(0, 20));
  ASSERT_TRUE(upload->Write(first));

  const auto wait_until = Clock::now() + std::chrono::seconds(20);
  while (frames < 3 && Clock::now() < wait_until) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_GE(frames, 3);

  const auto t0 = Clock::now();
  frames_at_term = frames.load();
  const int exit_code = server.Stop(SIGTERM, kGrace + 10);
  const double exited_after = SecondsSince(t0);
  streamer.join();
  const grpc::Status upload_status = upload->Finish();
  std::printf(
      "  grace %.0f s: exit %d after %.2f s; stream frames %d at SIGTERM, %d in all, ended %d; "
      "upload ended %d (%s)\n",
      kGrace, exit_code, exited_after, frames_at_term.load(), frames.load(), static_cast<int>(stream_end),
      static_cast<int>(upload_status.error_code()), upload_status.error_message().c_str());
  EXPECT_EQ(exit_code, 0) << ReadFile(server.log_file());
  EXPECT_LT(exited_after, kGrace + 5) << ReadFile(server.log_file());
  // Served during the grace (30 fps for most of 2 s), then ended with an error.
  EXPECT_GT(frames - frames_at_term, 10);
  EXPECT_NE(stream_end, grpc::StatusCode::OK);
  EXPECT_NE(upload_status.error_code(), grpc::StatusCode::OK);
  EXPECT_FALSE(upload_response.has_asset()) << "the half upload must not be imported";
}

}  // namespace
}  // namespace armature::testing
