// Uploads within stated bounds: a raw REST upload is streamed on to
// ImportAsset, so the server holds it about once (it held the body, a copy
// in chunk messages and the assembled file: 3×); at most
// --max-concurrent-uploads are received at once, over gRPC and REST alike.
#include <chrono>
#include <csignal>
#include <string>
#include <thread>
#include <vector>

#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>
#include <httplib.h>

#include "armature/client.h"
#include "armature/v1/assets.grpc.pb.h"
#include "support/client_helpers.h"
#include "support/process_memory.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

constexpr size_t kUploadBytes = size_t{250} << 20;
constexpr int64_t kUploadKb = kUploadBytes >> 10;

// 250 MiB that no parser takes: answered INVALID_ARGUMENT once received whole.
const std::string& BigUpload() {
  static const std::string bytes = [] {
    std::string b;
    b.reserve(kUploadBytes);
    while (b.size() < kUploadBytes) b += "x\n";  // short tokens: the BVH reader stops at the first
    return b;
  }();
  return bytes;
}

int PostUpload(int port, const std::string& name, std::string* body) {
  httplib::Client http("127.0.0.1", port);
  http.set_read_timeout(120);
  http.set_write_timeout(120);
  const auto r = http.Post("/v1/assets:import?filename=big.bvh&name=" + name, BigUpload(), "application/octet-stream");
  if (!r) return -1;
  *body = r->body;
  return r->status;
}

TEST(UploadMemory, ARestUploadIsHeldAboutOnce) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo"});
  const int64_t before = StatusKb(server.pid(), "VmRSS");
  std::string body;
  EXPECT_EQ(PostUpload(server.http_port(), "big", &body), 400) << body.substr(0, 300);
  const int64_t peak = StatusKb(server.pid(), "VmHWM");
  std::printf("  one 250 MiB REST upload: server peak %.0f MB (%.0f MB before)\n", peak / 1024.0, before / 1024.0);
  EXPECT_LT(peak - before, kUploadKb * 3 / 2) << "peak " << peak << " kB, before " << before << " kB";
}

TEST(UploadMemory, SixRestUploadsAtOnceStopAtTheCap) {
  // A refused upload's connection is closed after kDrainBytes: the client's
  // next write fails (EPIPE), which must not end this process.
  std::signal(SIGPIPE, SIG_IGN);
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-concurrent-uploads", "2"});
  const int64_t before = StatusKb(server.pid(), "VmRSS");
  std::vector<int> codes(6);
  std::vector<std::string> bodies(6);
  std::vector<std::thread> threads;
  for (int i = 0; i < 6; ++i)
    threads.emplace_back([&, i] { codes[i] = PostUpload(server.http_port(), "big" + std::to_string(i), &bodies[i]); });
  for (auto& t : threads) t.join();
  const int64_t peak = StatusKb(server.pid(), "VmHWM");
  std::printf("  six 250 MiB REST uploads at once: server peak %.0f MB (%.0f MB before)\n", peak / 1024.0,
              before / 1024.0);
  int received = 0;
  for (int i = 0; i < 6; ++i) {
    // Received and refused by the parser, or refused at the door: a 429, or
    // the connection closed before the client could send the rest (-1).
    EXPECT_TRUE(codes[i] == 400 || codes[i] == 429 || codes[i] == -1) << codes[i] << ": " << bodies[i].substr(0, 300);
    if (codes[i] == 429)
      EXPECT_NE(bodies[i].find("--max-concurrent-uploads"), std::string::npos) << bodies[i].substr(0, 300);
    received += codes[i] == 400;
  }
  EXPECT_LT(received, 6) << "none was refused at the door";
  EXPECT_LT(peak - before, 2 * kUploadKb * 3 / 2) << "peak " << peak << " kB, before " << before << " kB";
  EXPECT_EQ(server.Stop(SIGTERM), 0);
}

TEST(UploadMemory, AnUploadOverTheCapIsRefusedAtOnce) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-concurrent-uploads", "2"});
  auto channel = grpc::CreateChannel(server.target(), grpc::InsecureChannelCredentials());
  auto stub = v1::AssetService::NewStub(channel);
  // Two uploads held open, each with its first chunk sent.
  struct Open {
    grpc::ClientContext context;
    v1::ImportAssetResponse response;
    std::unique_ptr<grpc::ClientWriter<v1::ImportAssetRequest>> writer;
  };
  auto hold = [&](int i) {
    auto o = std::make_unique<Open>();
    o->writer = stub->ImportAsset(&o->context, &o->response);
    v1::ImportAssetRequest first;
    first.set_filename("held.bvh");
    first.set_name("held" + std::to_string(i));
    first.set_data(std::string(kArmBvh).substr(0, 20));
    EXPECT_TRUE(o->writer->Write(first));
    return o;
  };
  std::vector<std::unique_ptr<Open>> open;
  for (int i = 0; i < 2; ++i) open.push_back(hold(i));
  // A third is refused without its data being read. Until the two have reached
  // the server, a third may get in first: it is imported and deleted, and a held
  // upload it kept out (refused, so its stream is closed) is opened again.
  client::Client client(OptionsFor(server));
  grpc::Status third;
  ASSERT_TRUE(WaitFor(
      [&] {
        third = StatusOf([&] { client.Import({"arm.bvh", kArmBvh}, "third"); });
        if (third.ok()) {
          client.DeleteAsset("third");
          for (size_t i = 0; i < open.size(); ++i)
            if (!open[i]->writer->Write(v1::ImportAssetRequest())) open[i] = hold(static_cast<int>(i));
        }
        return !third.ok();
      },
      10));
  EXPECT_EQ(third.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << third.error_message();
  EXPECT_NE(third.error_message().find("--max-concurrent-uploads"), std::string::npos) << third.error_message();
  // The two finish; then there is room again.
  for (auto& o : open) {
    v1::ImportAssetRequest rest;
    rest.set_data(std::string(kArmBvh).substr(20));
    EXPECT_TRUE(o->writer->Write(rest));
    o->writer->WritesDone();
    const grpc::Status st = o->writer->Finish();
    EXPECT_TRUE(st.ok()) << st.error_message();
  }
  EXPECT_EQ(CodeOf([&] { client.Import({"arm.bvh", kArmBvh}, "third"); }), grpc::StatusCode::OK);
}

}  // namespace
}  // namespace armature::testing
