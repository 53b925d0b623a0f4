// Skinning throughput: ns per vertex for LBS and DQS with 4 influences and
// normals, on one core and with the worker pool. Compare DQS to LBS (and the
// threaded runs to the single-core ones) within the same run.
#include <benchmark/benchmark.h>

#include "armature/engine/mesh/skinning.h"
#include "cylinder_rig.h"

namespace armature {
namespace {

void BM_Skin(benchmark::State& state, SkinningMethod method, bool normals, bool parallel, bool morph) {
  const armature_bench::CylinderRig& rig = armature_bench::MakeCylinderRig(static_cast<int>(state.range(0)), morph);
  const size_t n = rig.mesh.vertex_count();
  std::vector<float> positions(3 * n), normal_out(normals ? 3 * n : 0);
  SkinningWorkspace ws;
  SkinningJob job;
  job.mesh = &rig.mesh;
  job.joint_world = rig.world;
  job.method = method;
  job.parallel = parallel;
  job.positions = positions;
  job.normals = normal_out;
  job.workspace = &ws;
  for (auto _ : state) {
    if (!job.Run().ok()) state.SkipWithError("skinning failed");
    benchmark::DoNotOptimize(positions.data());
    benchmark::ClobberMemory();
  }
  state.counters["vertices"] = static_cast<double>(n);
  // Seconds per vertex (printed with an SI prefix: "3.1n" = 3.1 ns).
  state.counters["per_vertex"] = benchmark::Counter(
      static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// 1024 rings × 64 = 65536 vertices; 256 rings = 16384 (a typical character).
BENCHMARK_CAPTURE(BM_Skin, lbs_normals_1core, SkinningMethod::kLinear, true, false, false)->Arg(256)->Arg(1024);
BENCHMARK_CAPTURE(BM_Skin, dqs_normals_1core, SkinningMethod::kDualQuaternion, true, false, false)->Arg(256)->Arg(1024);
BENCHMARK_CAPTURE(BM_Skin, lbs_positions_1core, SkinningMethod::kLinear, false, false, false)->Arg(1024);
BENCHMARK_CAPTURE(BM_Skin, dqs_positions_1core, SkinningMethod::kDualQuaternion, false, false, false)->Arg(1024);
BENCHMARK_CAPTURE(BM_Skin, lbs_normals_morph_1core, SkinningMethod::kLinear, true, false, true)->Arg(1024);
BENCHMARK_CAPTURE(BM_Skin, lbs_normals_pool, SkinningMethod::kLinear, true, true, false)->Arg(1024)->UseRealTime();
BENCHMARK_CAPTURE(BM_Skin, dqs_normals_pool, SkinningMethod::kDualQuaternion, true, true, false)
    ->Arg(1024)
    ->UseRealTime();

}  // namespace
}  // namespace armature
