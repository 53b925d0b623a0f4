// Skinning throughput: ns per vertex for LBS and DQS with 4 influences and
// normals, on one core and with the worker pool. Compare DQS to LBS (and the
// threaded runs to the single-core ones) within the same run.
#include <random>

#include <benchmark/benchmark.h>

#include "../tests/engine/testing/mesh_test_util.h"
#include "armature/engine/mesh/blendshape.h"
#include "armature/engine/kinematics/fk.h"
#include "armature/engine/math/rotation.h"
#include "armature/engine/mesh/skinning.h"

namespace armature {
namespace {

struct Rig {
  std::shared_ptr<Skeleton> skeleton;
  Mesh mesh;
  std::vector<Eigen::Affine3d> world;
};

// A cylinder along a 64-joint chain, every vertex with exactly 4 influences,
// posed with a bend and a twist on every joint.
const Rig& MakeRig(int rings, bool morph) {
  static std::map<std::pair<int, bool>, Rig> cache;
  auto [it, fresh] = cache.try_emplace({rings, morph});
  Rig& rig = it->second;
  if (!fresh) return rig;
  const int joints = 64, segments = 64;
  const double length = 0.25;
  rig.skeleton = test_util::MakeChain(joints, length);
  rig.mesh = test_util::MakeCylinder(0.1, joints * length, rings, segments);
  test_util::BindAlongZ(rig.mesh, *rig.skeleton, length, 4);
  if (morph) {
    MorphTarget t{"bulge", {}, {}, {}};
    for (uint32_t v = 0; v < rig.mesh.vertex_count(); v += 10) {
      t.vertices.push_back(v);
      t.position_deltas.emplace_back(0.01f, 0, 0);
    }
    rig.mesh.targets.push_back(t);
    rig.mesh.default_weights = {0.5f};
  }
  if (!FinalizeMesh(rig.mesh).ok()) std::abort();
  std::vector<Trs> pose = rig.skeleton->rest;
  for (size_t i = 0; i < pose.size(); ++i)
    pose[i].rotation = AxisRotation(Axis::kX, 0.05) * AxisRotation(Axis::kZ, 0.1 * static_cast<double>(i % 5));
  rig.world.resize(pose.size());
  ComputeWorld(*rig.skeleton, pose, rig.world);
  return rig;
}

void BM_Skin(benchmark::State& state, SkinningMethod method, bool normals, bool parallel, bool morph) {
  const Rig& rig = MakeRig(static_cast<int>(state.range(0)), morph);
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
  state.counters["per_vertex"] = benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate |
                                                                               benchmark::Counter::kInvert);
}

// 1024 rings × 64 = 65536 vertices; 256 rings = 16384 (a typical character).
BENCHMARK_CAPTURE(BM_Skin, lbs_normals_1core, SkinningMethod::kLinear, true, false, false)->Arg(256)->Arg(1024);
BENCHMARK_CAPTURE(BM_Skin, dqs_normals_1core, SkinningMethod::kDualQuaternion, true, false, false)->Arg(256)->Arg(1024);
BENCHMARK_CAPTURE(BM_Skin, lbs_positions_1core, SkinningMethod::kLinear, false, false, false)->Arg(1024);
BENCHMARK_CAPTURE(BM_Skin, dqs_positions_1core, SkinningMethod::kDualQuaternion, false, false, false)->Arg(1024);
BENCHMARK_CAPTURE(BM_Skin, lbs_normals_morph_1core, SkinningMethod::kLinear, true, false, true)->Arg(1024);
BENCHMARK_CAPTURE(BM_Skin, lbs_normals_pool, SkinningMethod::kLinear, true, true, false)->Arg(1024)->UseRealTime();
BENCHMARK_CAPTURE(BM_Skin, dqs_normals_pool, SkinningMethod::kDualQuaternion, true, true, false)->Arg(1024)->UseRealTime();

}  // namespace
}  // namespace armature
