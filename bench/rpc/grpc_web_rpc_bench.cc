// A big answer over each transport of the same server: SkinMesh on the
// 100,489-vertex skinned sheet (skinned_sheet.h; 2.4 MB of positions and
// normals) over gRPC, gRPC-Web (binary, on the HTTP port), REST with
// Accept: application/x-protobuf, and REST JSON. Every variant ends with the
// decoded SkinMeshResponse in hand, as a client would (HTTP: one keep-alive
// connection with TCP_NODELAY, as browsers use). The counter vs_grpc is each
// variant's time over gRPC's, timed in the same iterations (the goal for
// gRPC-Web binary: at most 3).
#include <chrono>
#include <stdexcept>

#include <benchmark/benchmark.h>
#include <google/protobuf/util/json_util.h>

#include "armature/v1/meshes.grpc.pb.h"
#include "rpc_bench_server.h"
#include "skinned_sheet.h"

// After Eigen (skinned_sheet.h): httplib brings <resolv.h>, whose _res macro
// breaks Eigen's headers.
#include <httplib.h>

namespace {

using armature_bench::Server;
using Clock = std::chrono::steady_clock;

armature::v1::SkinMeshRequest SkinRequest() {
  armature::v1::SkinMeshRequest r;
  r.set_mesh(armature_bench::ImportedSkinnedSheet());
  r.set_clip(armature_bench::kSkinnedSheetClip);
  r.set_time(0.5);
  return r;
}

armature::v1::SkinMeshResponse ViaGrpc(const armature::v1::SkinMeshRequest& r) { return Server().client->SkinMesh(r); }

httplib::Client& Http() {
  static httplib::Client http = [] {
    httplib::Client c("127.0.0.1", Server().server->http_port());
    c.set_keep_alive(true);
    c.set_tcp_nodelay(true);  // as browsers do; else Nagle holds the body for the server's delayed ACK (40 ms)
    c.set_read_timeout(60);
    return c;
  }();
  return http;
}

armature::v1::SkinMeshResponse ViaGrpcWeb(const armature::v1::SkinMeshRequest& r) {
  const std::string message = r.SerializeAsString();
  const auto n = static_cast<uint32_t>(message.size());
  std::string frame{'\0', static_cast<char>(n >> 24), static_cast<char>(n >> 16), static_cast<char>(n >> 8),
                    static_cast<char>(n)};
  frame += message;
  const auto res = Http().Post("/armature.v1.MeshService/SkinMesh", frame, "application/grpc-web+proto");
  if (!res || res->status != 200 || res->body.size() < 5 || res->body[0] != '\0')
    throw std::runtime_error("gRPC-Web SkinMesh failed");
  const auto* p = reinterpret_cast<const unsigned char*>(res->body.data());
  const uint32_t length = (uint32_t{p[1]} << 24) | (uint32_t{p[2]} << 16) | (uint32_t{p[3]} << 8) | p[4];
  armature::v1::SkinMeshResponse out;
  if (length > res->body.size() - 5 || !out.ParseFromArray(p + 5, static_cast<int>(length)) ||
      res->body.find("grpc-status: 0", 5 + length) == std::string::npos)
    throw std::runtime_error("gRPC-Web SkinMesh: bad answer");
  return out;
}

std::string RestPath(const armature::v1::SkinMeshRequest& r) { return "/v1/meshes/" + r.mesh() + ":skin"; }

armature::v1::SkinMeshResponse ViaRestProtobuf(const armature::v1::SkinMeshRequest& r) {
  const auto res =
      Http().Post(RestPath(r), {{"Accept", "application/x-protobuf"}}, r.SerializeAsString(), "application/x-protobuf");
  armature::v1::SkinMeshResponse out;
  if (!res || res->status != 200 || !out.ParseFromString(res->body))
    throw std::runtime_error("REST protobuf SkinMesh failed");
  return out;
}

armature::v1::SkinMeshResponse ViaRestJson(const armature::v1::SkinMeshRequest& r) {
  std::string body;
  (void)google::protobuf::util::MessageToJsonString(r, &body);
  const auto res = Http().Post(RestPath(r), body, "application/json");
  armature::v1::SkinMeshResponse out;
  if (!res || res->status != 200 || !google::protobuf::util::JsonStringToMessage(res->body, &out).ok())
    throw std::runtime_error("REST JSON SkinMesh failed");
  return out;
}

template <armature::v1::SkinMeshResponse (*Call)(const armature::v1::SkinMeshRequest&)>
void BM_SkinMesh100k(benchmark::State& state) {
  const auto r = SkinRequest();
  const auto first = Call(r);
  ViaGrpc(r);  // warm up both
  if (first.vertex_count() != static_cast<int>(armature_bench::Sheet().positions.rows()) ||
      first.positions_size() != 3 * first.vertex_count())
    return state.SkipWithError("unexpected SkinMesh answer");
  // Each iteration also times one gRPC call (not counted in the variant's
  // time), so the ratio compares the two under the same machine load.
  double seconds = 0, grpc_seconds = 0;
  for (auto _ : state) {
    auto start = Clock::now();
    benchmark::DoNotOptimize(Call(r));
    const double t = std::chrono::duration<double>(Clock::now() - start).count();
    state.SetIterationTime(t);
    seconds += t;
    start = Clock::now();
    benchmark::DoNotOptimize(ViaGrpc(r));
    grpc_seconds += std::chrono::duration<double>(Clock::now() - start).count();
  }
  state.counters["vs_grpc"] = seconds / grpc_seconds;
  state.counters["grpc_ms"] = 1e3 * grpc_seconds / static_cast<double>(state.iterations());
  state.counters["MB"] = static_cast<double>(first.ByteSizeLong()) / 1e6;
}

BENCHMARK_TEMPLATE(BM_SkinMesh100k, ViaGrpc)
    ->Name("BM_SkinMesh100k/grpc")
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_SkinMesh100k, ViaGrpcWeb)
    ->Name("BM_SkinMesh100k/grpc_web_binary")
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_SkinMesh100k, ViaRestProtobuf)
    ->Name("BM_SkinMesh100k/rest_protobuf")
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_SkinMesh100k, ViaRestJson)
    ->Name("BM_SkinMesh100k/rest_json")
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
