// GET /metrics in the Prometheus text format, and the per-call request log.
#include <atomic>
#include <cstdio>
#include <map>
#include <regex>
#include <sstream>
#include <thread>

#include <grpcpp/generic/generic_stub.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/testing/generated_meshes.h"
#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/http_get.h"
#include "support/metrics_scrape.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {
using nlohmann::json;

constexpr char kEvaluate[] = "armature.v1.PoseService/EvaluateClip";

std::string Bucket(const std::string& method, const std::string& le) {
  return "armature_rpc_duration_seconds_bucket{method=\"" + method + "\",le=\"" + le + "\"}";
}

TEST(Metrics, HistogramsCountsAndAssetGauges) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  client.Import({"arm.bvh", kArmBvh});
  v1::EvaluateClipRequest r;
  r.set_clip("arm");
  r.add_times(0.5);
  for (int i = 0; i < 3; ++i) client.EvaluateClip(r);
  EXPECT_EQ(CodeOf([&] { client.GetClip("nope"); }), grpc::StatusCode::NOT_FOUND);

  const HttpResponse raw = HttpGet("http://127.0.0.1:" + std::to_string(server.http_port()) + "/metrics");
  EXPECT_NE(raw.body.find("# TYPE armature_rpc_duration_seconds histogram"), std::string::npos) << raw.body;
  const auto m = ParseSamples(raw.body);
  // The histogram of EvaluateClip: three calls, cumulative buckets ending in +Inf = count.
  const std::string method = kEvaluate;
  EXPECT_EQ(m.at(Bucket(method, "+Inf")), 3);
  EXPECT_EQ(m.at("armature_rpc_duration_seconds_count{method=\"" + method + "\"}"), 3);
  EXPECT_GT(m.at("armature_rpc_duration_seconds_sum{method=\"" + method + "\"}"), 0);
  double previous = 0;
  for (const char* le : {"0.0005", "0.001", "0.0025", "0.005", "0.01", "0.025", "0.05", "0.1", "0.25", "0.5", "1",
                         "2.5", "5", "10", "30", "60", "+Inf"}) {
    const double n = m.at(Bucket(method, le));
    EXPECT_GE(n, previous) << "le=" << le;
    previous = n;
  }
  // Counts by status code.
  EXPECT_EQ(m.at("armature_rpc_requests_total{method=\"" + method + "\",code=\"OK\"}"), 3);
  EXPECT_EQ(m.at("armature_rpc_requests_total{method=\"armature.v1.AssetService/GetClip\",code=\"NOT_FOUND\"}"), 1);
  EXPECT_EQ(m.at("armature_rpc_requests_total{method=\"armature.v1.AssetService/ImportAsset\",code=\"OK\"}"), 1);
  EXPECT_EQ(m.at("armature_rpc_in_flight{method=\"" + method + "\"}"), 0);
  // The store: one asset giving one skeleton and one clip.
  EXPECT_EQ(m.at("armature_assets_loaded{kind=\"asset\"}"), 1);
  EXPECT_EQ(m.at("armature_assets_loaded{kind=\"clip\"}"), 1);
  EXPECT_EQ(m.at("armature_assets_loaded{kind=\"skeleton\"}"), 1);
  EXPECT_EQ(m.at("armature_assets_source_bytes"), std::string(kArmBvh).size());
  // Memory: at least the key data (2 joints × 3 frames × (a time + a quaternion)), well under a megabyte.
  const double small = m.at("armature_assets_memory_bytes");
  EXPECT_GE(small, 2 * 3 * (8 + 32));
  EXPECT_LT(small, 1 << 20);
  // A 1000-frame clip adds its runtime form, as GetClip reports it, and
  // less than the file form's 2 × 1000 rotation keys would take: the
  // server holds the compressed form only.
  client.Import({"long.bvh", ArmBvhWithFrames(1000)});
  const v1::ClipInfo long_clip = client.GetClip("long");
  EXPECT_FALSE(long_clip.exact());
  const double grown = Scrape(server).at("armature_assets_memory_bytes") - small;
  EXPECT_GE(grown, long_clip.runtime_bytes());
  EXPECT_LT(grown, 2 * 1000 * (8 + 32));
  std::printf("a 2-joint, 1000-frame clip: +%g bytes (runtime form %lld bytes)\n", grown,
              static_cast<long long>(long_clip.runtime_bytes()));
}

// A mesh adds at least its raw vertex data: float positions and 32-bit triangle indices.
TEST(Metrics, ImportedMeshesCountInAssetMemory) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  const double before = Scrape(server).at("armature_assets_memory_bytes");
  const fixtures::GeneratedMesh grid = fixtures::MakeGrid(100, 100, 1, 1);
  const auto imported = client.Import({"grid.obj", fixtures::ToObj(grid)}, "grid");
  ASSERT_EQ(imported.asset().meshes_size(), 1);
  const double vertices = 100 * 100, triangles = 99 * 99 * 2;
  const double raw = vertices * 3 * sizeof(float) + triangles * 3 * sizeof(uint32_t);
  const auto m = Scrape(server);
  EXPECT_EQ(m.at("armature_assets_loaded{kind=\"mesh\"}"), 1);
  const double grown = m.at("armature_assets_memory_bytes") - before;
  std::printf("a %g-vertex, %g-triangle mesh: +%g bytes (raw vertex data %g)\n", vertices, triangles, grown, raw);
  EXPECT_GE(grown, raw);
  // Copies of the vertex data (normals, the skinning layout's positions and order) but nothing per pair of vertices.
  EXPECT_LT(grown, 4 * raw);
  client.DeleteAsset("grid");
  EXPECT_EQ(Scrape(server).at("armature_assets_memory_bytes"), before);
}

// A call to a method the server does not have, through gRPC's generic stub.
grpc::StatusCode CallUnknownMethod(client::Client& client, const std::string& method) {
  grpc::GenericStub stub(client.channel());
  grpc::CompletionQueue cq;
  grpc::ClientContext context;
  client.Prepare(context);
  grpc::ByteBuffer request, response;
  grpc::Status status;
  auto call = stub.PrepareUnaryCall(&context, method, request, &cq);
  call->StartCall();
  call->Finish(&response, &status, nullptr);
  void* tag = nullptr;
  bool ok = false;
  cq.Next(&tag, &ok);
  return status.error_code();
}

TEST(Metrics, MadeUpMethodsShareOneLabel) {
  TempDir data;
  ServerProcess server(data.path());
  client::Client client(OptionsFor(server));
  for (int i = 0; i < 3; ++i)
    EXPECT_EQ(CallUnknownMethod(client, "/made.Up/Method" + std::to_string(i)), grpc::StatusCode::UNIMPLEMENTED);
  const HttpResponse r = HttpGet("http://127.0.0.1:" + std::to_string(server.http_port()) + "/metrics");
  EXPECT_EQ(r.body.find("made.Up"), std::string::npos) << r.body;
  EXPECT_EQ(ParseSamples(r.body).at("armature_rpc_requests_total{method=\"unknown\",code=\"UNIMPLEMENTED\"}"), 3);
}

TEST(Metrics, StreamsInFlightGauge) {
  TempDir data;
  ServerProcess server(data.path());
  client::Client client(OptionsFor(server));
  std::atomic<int> frames{0};
  std::atomic<bool> stop{false};
  std::thread streamer([&] {
    v1::StreamClipRequest s;
    s.set_clip("demo_walk");
    s.set_loop(true);
    client.StreamClip(s, [&](const v1::PoseFrame&) {
      ++frames;
      return !stop;
    });
  });
  ASSERT_TRUE(WaitFor([&] { return frames > 2; }, 30));
  auto m = Scrape(server);
  EXPECT_EQ(m.at("armature_streams_in_flight"), 1);
  EXPECT_EQ(m.at("armature_rpc_in_flight{method=\"armature.v1.PoseService/StreamClip\"}"), 1);
  stop = true;
  streamer.join();
  EXPECT_TRUE(WaitFor([&] { return Scrape(server).at("armature_streams_in_flight") == 0; }, 30));
  m = Scrape(server);
  EXPECT_EQ(m.at("armature_rpc_in_flight{method=\"armature.v1.PoseService/StreamClip\"}"), 0);
  EXPECT_EQ(m.at("armature_rpc_duration_seconds_count{method=\"armature.v1.PoseService/StreamClip\"}"), 1);
}

TEST(Metrics, OneJsonLogLinePerCallWithItsRequestId) {
  TempDir data;
  ServerProcess server(data.path(), {"--log-format", "json"});
  client::Client client(OptionsFor(server));
  // A caller's request id is used, and sent back.
  v1::EvaluateClipRequest r;
  r.set_clip("demo_walk");
  r.add_times(0.5);
  grpc::ClientContext context;
  client.Prepare(context);
  context.AddMetadata("x-request-id", "test-req-42");
  v1::EvaluateClipResponse response;
  ASSERT_TRUE(v1::PoseService::NewStub(client.channel())->EvaluateClip(&context, r, &response).ok());
  const auto echoed = context.GetServerInitialMetadata().find("x-request-id");
  ASSERT_NE(echoed, context.GetServerInitialMetadata().end());
  EXPECT_EQ(std::string(echoed->second.data(), echoed->second.size()), "test-req-42");
  // Without one, the server makes one; errors carry their message.
  EXPECT_EQ(CodeOf([&] { client.GetClip("nope"); }), grpc::StatusCode::NOT_FOUND);
  EXPECT_TRUE(client.Healthy());

  std::vector<json> rpcs;
  ASSERT_TRUE(WaitFor(
      [&] {
        rpcs.clear();
        std::istringstream lines(ReadFile(server.log_file()));
        for (std::string line; std::getline(lines, line);) {
          const json j = json::parse(line, nullptr, false);
          EXPECT_FALSE(j.is_discarded()) << "not JSON: " << line;
          if (!j.is_discarded() && j.value("msg", "") == "rpc") rpcs.push_back(j);
        }
        return rpcs.size() >= 2;
      },
      10));
  ASSERT_EQ(rpcs.size(), 2u) << "health checks log at debug level only";
  EXPECT_EQ(rpcs[0]["method"], kEvaluate);
  EXPECT_EQ(rpcs[0]["code"], "OK");
  EXPECT_EQ(rpcs[0]["request_id"], "test-req-42");
  EXPECT_EQ(rpcs[0]["level"], "info");
  EXPECT_GE(rpcs[0]["duration_ms"].get<double>(), 0);
  EXPECT_NE(rpcs[0]["peer"].get<std::string>().find("127.0.0.1"), std::string::npos) << rpcs[0].dump();
  EXPECT_EQ(rpcs[1]["method"], "armature.v1.AssetService/GetClip");
  EXPECT_EQ(rpcs[1]["code"], "NOT_FOUND");
  EXPECT_TRUE(std::regex_match(rpcs[1]["request_id"].get<std::string>(), std::regex("[0-9a-f]{16}"))) << rpcs[1];
  EXPECT_NE(rpcs[1]["error"].get<std::string>().find("nope"), std::string::npos);
}

}  // namespace
}  // namespace armature::testing
