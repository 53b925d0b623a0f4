// Unary Deform over a real gRPC connection on the 100k-vertex sheet
// (sheet_mesh.h), one handle at the centre, the boundary fixed: the first
// call for a setup (a cache miss: model, factorization, solve) against
// repeated calls with new handle positions (a hit: solve only), with the
// empty RPC (BM_EmptyRpc_HealthCheck in evaluate_rpc_bench.cc, same server,
// same run) as the baseline. The answer is 300k floats; the in-process
// protobuf and JSON encodings of such an answer are measured too, to show how
// much of a hit's round trip is the payload.
#include <string>
#include <string_view>
#include <vector>

#include <benchmark/benchmark.h>

#include "armature/v1/deform.grpc.pb.h"
#include "rpc_bench_server.h"
#include "sheet_rpc.h"
#include "server/deform/deform_handlers.h"
#include "server/host/gateway/rest/json/json_codec.h"

namespace {

using armature_bench::Server;
namespace v1 = armature::v1;

constexpr int kSide = armature_bench::kSheetSide;
constexpr uint32_t kCentre = static_cast<uint32_t>((kSide / 2) * kSide + kSide / 2);

// The boundary fixed, `handle` lifted by `lift`.
v1::DeformRequest SheetRequest(v1::DeformMethod method, uint32_t handle, double lift) {
  v1::DeformRequest r;
  r.set_mesh(armature_bench::ImportedSheet());
  r.set_method(method);
  r.set_weights(method == v1::ARAP ? v1::COTANGENT : v1::UNIFORM);
  static const std::vector<uint32_t> boundary = armature_bench::SheetConstraints(1).fixed;
  r.mutable_fixed()->Add(boundary.begin(), boundary.end());
  auto* h = r.add_handles();
  h->set_index(handle);
  const auto& rest = armature_bench::Sheet().positions;
  for (int a = 0; a < 3; ++a) h->add_position(rest(handle, a) + (a == 2 ? lift : 0.0));
  return r;
}

v1::DeformResponse Deform(const v1::DeformRequest& r) {
  static const auto stub = v1::DeformService::NewStub(Server().client->channel());
  return Server().client->Call(&v1::DeformService::Stub::Deform, *stub, r);
}

double CacheCounter(std::string_view name) {
  const std::string text = Server().server->metrics().Render();
  const size_t at = text.find("\n" + std::string(name) + " ");
  return at == std::string::npos ? -1 : std::stod(text.substr(at + name.size() + 2));
}

// Puts the hits and misses the benchmark caused in its counters.
struct CacheCounts {
  double hits = CacheCounter("armature_deform_cache_hits_total");
  double misses = CacheCounter("armature_deform_cache_misses_total");
  void Report(benchmark::State& state) const {
    state.counters["cache_hits"] = CacheCounter("armature_deform_cache_hits_total") - hits;
    state.counters["cache_misses"] = CacheCounter("armature_deform_cache_misses_total") - misses;
    state.counters["cache_MiB"] = CacheCounter("armature_deform_cache_bytes") / (1 << 20);
  }
};

// The handle's lift on call `step` of a drag: up to 0.2 (the sheet is 2 wide).
double Lift(int step) { return 0.002 * (1 + step % 100); }

// Each call names a handle no earlier call used: every one factors.
void Miss(benchmark::State& state, v1::DeformMethod method) {
  static uint32_t next_handle = kCentre + 1;
  armature_bench::ImportedSheet();
  const CacheCounts before;
  int step = 0, iterations = 0;
  for (auto _ : state) iterations += Deform(SheetRequest(method, next_handle++, Lift(step++))).iterations();
  before.Report(state);
  state.counters["arap_iterations"] = benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
}

// One call outside the timing factors; the timed ones move the handle.
void Hit(benchmark::State& state, v1::DeformMethod method) {
  Deform(SheetRequest(method, kCentre, Lift(0)));
  const CacheCounts before;
  int step = 0, iterations = 0;
  for (auto _ : state) iterations += Deform(SheetRequest(method, kCentre, Lift(++step))).iterations();
  before.Report(state);
  state.counters["arap_iterations"] = benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
}

void BM_Deform_Sheet100k_Laplacian_Miss(benchmark::State& state) { Miss(state, v1::LAPLACIAN); }
BENCHMARK(BM_Deform_Sheet100k_Laplacian_Miss)->UseRealTime()->Unit(benchmark::kMillisecond)->Iterations(5);

void BM_Deform_Sheet100k_Laplacian_Hit(benchmark::State& state) { Hit(state, v1::LAPLACIAN); }
BENCHMARK(BM_Deform_Sheet100k_Laplacian_Hit)->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_Deform_Sheet100k_Arap_Miss(benchmark::State& state) { Miss(state, v1::ARAP); }
BENCHMARK(BM_Deform_Sheet100k_Arap_Miss)->UseRealTime()->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_Deform_Sheet100k_Arap_Hit(benchmark::State& state) { Hit(state, v1::ARAP); }
BENCHMARK(BM_Deform_Sheet100k_Arap_Hit)->UseRealTime()->Unit(benchmark::kMillisecond);

// The server's work for a hit without gRPC: the cache lookup, the solve and
// filling the response (the bench server's store, a cache of its own).
void BM_Deform_Sheet100k_Laplacian_HitInProcess(benchmark::State& state) {
  namespace server = armature::server;
  armature_bench::ImportedSheet();
  const server::AssetStore& store = Server().server->store();
  server::DeformerCache cache(size_t{256} << 20);
  const server::Limits limits;
  v1::DeformResponse response;
  if (auto st =
          server::Deform(cache, store.Snapshot(), limits, SheetRequest(v1::LAPLACIAN, kCentre, Lift(0)), &response);
      !st.ok())
    return state.SkipWithError(st.message().c_str());
  int step = 0;
  for (auto _ : state) {
    const auto st =
        server::Deform(cache, store.Snapshot(), limits, SheetRequest(v1::LAPLACIAN, kCentre, Lift(++step)), &response);
    if (!st.ok()) return state.SkipWithError(st.message().c_str());
  }
  state.counters["cache_hits"] = static_cast<double>(cache.stats().hits);
}
BENCHMARK(BM_Deform_Sheet100k_Laplacian_HitInProcess)->UseRealTime()->Unit(benchmark::kMillisecond);

// gRPC's share of the payload: BM_DeformResponse_Serialize/_Parse in deform_rpc_bench.cc.

// What the REST gateway adds for a browser: the answer printed as JSON.
void BM_DeformResponse_Sheet100k_GatewayJson(benchmark::State& state) {
  const v1::DeformResponse answer = armature_bench::SheetAnswer();
  size_t size = 0;
  for (auto _ : state) {
    const std::string json = armature::server::gateway::MessageToJson(answer);
    size = json.size();
    benchmark::DoNotOptimize(json.data());
  }
  state.counters["MiB"] = static_cast<double>(size) / (1 << 20);
}
BENCHMARK(BM_DeformResponse_Sheet100k_GatewayJson)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
