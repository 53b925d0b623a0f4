// Mesh deformation over a real gRPC connection on a ~100k-vertex mesh (the
// 317 × 317 sheet of laplacian_bench.cc, imported as OBJ bytes made here).
// Measured: DeformSession setup (factorization and the rest-shape answer),
// one move round trip (write + read) with 1 and 64 handles, Laplacian
// (uniform) and ARAP (cotangent) — the drag budget is 10 ms per move — and
// the parts of a move, to see where its time goes: the server's handler
// alone (solve + filling the response, no gRPC) and the response's
// serialization and parsing. The baseline is the empty RPC
// (BM_EmptyRpc_HealthCheck in evaluate_rpc_bench.cc, same server, same run):
// report ratios to it.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "rpc_bench_server.h"
#include "server/deform/mesh_deformer.h"
#include "sheet_rpc.h"

namespace {

namespace v1 = armature::v1;
using armature_bench::Server;
using armature_bench::SheetAnswer;

constexpr int kTargetSets = 100;  // drag steps cycled through

// Args: (handle patch side: 1 → 1 handle, 8 → 64; method: 0 Laplacian uniform, 1 ARAP cotangent).
struct Drag {
  armature::DeformationConstraints constraints;
  v1::DeformSessionStart start;
  std::vector<std::vector<double>> targets;  // kTargetSets drag steps

  explicit Drag(const benchmark::State& state) {
    constraints = armature_bench::SheetConstraints(static_cast<int>(state.range(0)));
    v1::DeformSetup* setup = start.mutable_setup();
    setup->set_mesh(armature_bench::ImportedSheet());
    const bool arap = state.range(1) == 1;
    setup->set_method(arap ? v1::ARAP : v1::LAPLACIAN);
    setup->set_weights(arap ? v1::COTANGENT : v1::UNIFORM);
    setup->mutable_fixed()->Add(constraints.fixed.begin(), constraints.fixed.end());
    start.mutable_handle_indices()->Add(constraints.handles.begin(), constraints.handles.end());
    for (int step = 1; step <= kTargetSets; ++step)
      targets.push_back(armature_bench::SheetDragTargets(constraints, step));
  }
  const std::vector<double>& Targets(int64_t step) const { return targets[static_cast<size_t>(step % kTargetSets)]; }
};

// 1 and 64 handles, Laplacian and ARAP, in ms of wall time.
void DragCases(benchmark::internal::Benchmark* b) {
  b->ArgNames({"patch", "arap"})->Unit(benchmark::kMillisecond)->UseRealTime();
  for (int arap : {0, 1})
    for (int patch : {1, 8}) b->Args({patch, arap});
}

void Label(benchmark::State& state, const v1::DeformResponse& answer) {
  state.SetLabel(std::string(state.range(1) ? "arap" : "laplacian") + ", " +
                 std::to_string(state.range(0) * state.range(0)) + " handle(s)");
  state.counters["vertices"] = answer.positions_size() / 3;
  state.counters["arap_rounds"] = answer.iterations();
}

// Open (factor, answer the rest shape) and close a session.
void BM_DeformRpc_SessionSetup(benchmark::State& state) {
  const Drag drag(state);
  v1::DeformResponse answer;
  for (auto _ : state) {
    auto session = Server().client->OpenDeformSession(drag.start);
    answer = session->last();
    session->Close();
  }
  Label(state, answer);
}
BENCHMARK(BM_DeformRpc_SessionSetup)->Apply(DragCases)->Iterations(2);

// One drag step: the handle positions out, every vertex position back.
void BM_DeformRpc_Move(benchmark::State& state) {
  const Drag drag(state);
  auto session = Server().client->OpenDeformSession(drag.start);
  int64_t step = 0;
  for (auto _ : state) benchmark::DoNotOptimize(session->Move(drag.Targets(++step)).positions_size());
  Label(state, session->last());
  session->Close();
}
BENCHMARK(BM_DeformRpc_Move)->Apply(DragCases);

// The session's handler without gRPC: solve and fill the response.
void BM_DeformHandler_Move(benchmark::State& state) {
  const Drag drag(state);
  armature::server::Limits limits;
  auto deformer = armature::server::MeshDeformer::Create(*Server().server->store().Snapshot(), limits,
                                                         drag.start.setup(), drag.constraints.handles);
  if (!deformer.ok()) return state.SkipWithError(deformer.status().message().c_str());
  v1::DeformResponse response;
  int64_t step = 0;
  for (auto _ : state) {
    response.Clear();
    const armature::Status st = deformer->Solve(drag.Targets(++step), "move", &response);
    if (!st.ok()) return state.SkipWithError(st.message().c_str());
  }
  Label(state, response);
}
BENCHMARK(BM_DeformHandler_Move)->Apply(DragCases);

void BM_DeformResponse_Serialize(benchmark::State& state) {
  const v1::DeformResponse r = SheetAnswer();
  std::string bytes;
  for (auto _ : state) {
    r.SerializeToString(&bytes);
    benchmark::DoNotOptimize(bytes.data());
  }
  state.SetBytesProcessed(state.iterations() * static_cast<int64_t>(bytes.size()));
}
BENCHMARK(BM_DeformResponse_Serialize)->Unit(benchmark::kMillisecond);

void BM_DeformResponse_Parse(benchmark::State& state) {
  const std::string bytes = SheetAnswer().SerializeAsString();
  v1::DeformResponse r;
  for (auto _ : state) {
    if (!r.ParseFromString(bytes)) return state.SkipWithError("parse failed");
    benchmark::DoNotOptimize(r.positions_size());
  }
  state.SetBytesProcessed(state.iterations() * static_cast<int64_t>(bytes.size()));
}
BENCHMARK(BM_DeformResponse_Parse)->Unit(benchmark::kMillisecond);

}  // namespace
