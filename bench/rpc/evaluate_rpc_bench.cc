// The hot path over a real gRPC connection: EvaluateClip round trips, with an
// empty RPC (grpc.health.v1 Check) on the same server as the baseline. The
// figure that matters is the ratio of the two.
#include <filesystem>
#include <memory>

#include <benchmark/benchmark.h>

#include "grpc/health/v1/health.grpc.pb.h"
#include "rpc_bench_server.h"

namespace {

using armature_bench::Server;

void BM_EmptyRpc_HealthCheck(benchmark::State& state) {
  auto stub = grpc::health::v1::Health::NewStub(Server().client->channel());
  grpc::health::v1::HealthCheckRequest request;
  grpc::health::v1::HealthCheckResponse response;
  for (auto _ : state) {
    grpc::ClientContext context;
    benchmark::DoNotOptimize(stub->Check(&context, request, &response));
  }
}
BENCHMARK(BM_EmptyRpc_HealthCheck)->UseRealTime();

void Evaluate(benchmark::State& state, const std::string& clip, int times) {
  armature::v1::EvaluateClipRequest r;
  r.set_clip(clip);
  r.set_space(armature::v1::WORLD);
  for (int i = 0; i < times; ++i) r.add_times(0.01 * i);
  for (auto _ : state) benchmark::DoNotOptimize(Server().client->EvaluateClip(r));
  state.SetItemsProcessed(state.iterations() * times);
}

void BM_Evaluate_DemoWalk_OnePose(benchmark::State& state) { Evaluate(state, "demo_walk", 1); }
BENCHMARK(BM_Evaluate_DemoWalk_OnePose)->UseRealTime();

void BM_Evaluate_Cmu_OnePose(benchmark::State& state) {
  if (!Server().has_cmu) return state.SkipWithError("../shared/data/bvh/cmu_01_01.bvh not present");
  Evaluate(state, "cmu", 1);
}
BENCHMARK(BM_Evaluate_Cmu_OnePose)->UseRealTime();

void BM_Evaluate_Cmu_100Poses(benchmark::State& state) {
  if (!Server().has_cmu) return state.SkipWithError("../shared/data/bvh/cmu_01_01.bvh not present");
  Evaluate(state, "cmu", 100);
}
BENCHMARK(BM_Evaluate_Cmu_100Poses)->UseRealTime();

}  // namespace
