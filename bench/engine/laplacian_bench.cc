// Laplacian editing and ARAP on a 100k-vertex mesh (a 317 × 317 wavy sheet):
// factorization time, time per drag (must stay ≤ 10 ms for 60 Hz dragging)
// and time per ARAP round. The baseline is one sparse product δ = L·V on the
// same mesh, so figures can be read as ratios to it.
#include <benchmark/benchmark.h>

#include <memory>
#include <vector>

#include "armature/engine/deform/arap.h"
#include "armature/engine/deform/laplacian_editor.h"
#include "sheet_mesh.h"

namespace armature {
namespace {

using armature_bench::Sheet;
using armature_bench::SheetConstraints;

std::shared_ptr<const LaplacianModel> SheetModel(LaplacianWeights weights) {
  static std::shared_ptr<const LaplacianModel> models[2];
  auto& model = models[weights == LaplacianWeights::kCotangent];
  if (!model) {
    LaplacianModelOptions options;
    options.weights = weights;
    model = *BuildLaplacianModel(Sheet().positions, Sheet().triangles, options);
  }
  return model;
}

// Puts the solver's size in the counters, or fails the benchmark with its
// status. Returns whether there is a solver to run.
template <class Solver>
bool CheckSolver(benchmark::State& state, const StatusOr<Solver>& solver) {
  if (!solver.ok()) {
    state.SkipWithError(solver.status().message().c_str());
    return false;
  }
  state.counters["handles"] = static_cast<double>(solver->handle_count());
  state.counters["unknowns"] = static_cast<double>(solver->unknown_count());
  state.counters["factor_MiB"] = static_cast<double>(solver->factorization_bytes()) / (1 << 20);
  state.counters["total_MiB"] = static_cast<double>(solver->memory_bytes()) / (1 << 20);
  return true;
}

// Laplacian benchmarks take (handle patch side, handle basis 0/1, ROI radius).
DeformationConstraints ConstraintsFromArgs(const benchmark::State& state) {
  return SheetConstraints(static_cast<int>(state.range(0)), static_cast<int>(state.range(2)));
}
DeformationSolverOptions OptionsFromArgs(const benchmark::State& state) {
  DeformationSolverOptions options;
  options.drag_update = state.range(1) ? DragUpdate::kHandleBasis : DragUpdate::kBackSubstitution;
  return options;
}

void BM_Baseline_LaplacianTimesPositions(benchmark::State& state) {
  const auto model = SheetModel(LaplacianWeights::kUniform);
  Eigen::MatrixX3d delta(model->rest_positions.rows(), 3);
  for (auto _ : state) {
    delta.noalias() = model->laplacian * model->rest_positions;
    benchmark::DoNotOptimize(delta.data());
  }
}
BENCHMARK(BM_Baseline_LaplacianTimesPositions)->Unit(benchmark::kMillisecond);

void BM_LaplacianModelBuild(benchmark::State& state) {
  LaplacianModelOptions options;
  options.weights = state.range(0) ? LaplacianWeights::kCotangent : LaplacianWeights::kUniform;
  for (auto _ : state) {
    auto model = BuildLaplacianModel(Sheet().positions, Sheet().triangles, options);
    benchmark::DoNotOptimize(model.ok());
  }
  state.SetLabel(options.weights == LaplacianWeights::kCotangent ? "cotangent" : "uniform");
}
BENCHMARK(BM_LaplacianModelBuild)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3);

// Create(): normal equations, symbolic + numeric LDLᵀ, and under kHandleBasis
// one back-substitution per handle. Args: handles patch side, basis (0/1), ROI radius.
void BM_LaplacianFactor(benchmark::State& state) {
  const auto model = SheetModel(LaplacianWeights::kUniform);
  const DeformationConstraints c = ConstraintsFromArgs(state);
  for (auto _ : state)
    if (!CheckSolver(state, DeformationSolver::Create(model, c, OptionsFromArgs(state)))) return;
}
BENCHMARK(BM_LaplacianFactor)
    ->ArgNames({"patch", "basis", "roi"})
    ->Args({1, 0, 0})
    ->Args({1, 1, 0})
    ->Args({4, 1, 0})
    ->Args({8, 1, 0})
    ->Args({4, 1, 60})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

// One drag: new handle positions in, all 100k vertex positions out.
void BM_LaplacianDrag(benchmark::State& state) {
  const auto model = SheetModel(LaplacianWeights::kUniform);
  const DeformationConstraints c = ConstraintsFromArgs(state);
  const auto solver = DeformationSolver::Create(model, c, OptionsFromArgs(state));
  if (!CheckSolver(state, solver)) return;
  std::vector<double> out(3 * model->vertex_count());
  int step = 0;
  for (auto _ : state) {
    state.PauseTiming();
    const std::vector<double> targets = armature_bench::SheetDragTargets(c, ++step);
    state.ResumeTiming();
    const Status st = solver->Solve(targets, out);
    benchmark::DoNotOptimize(out.data());
    if (!st.ok()) state.SkipWithError(st.message().c_str());
  }
}
BENCHMARK(BM_LaplacianDrag)
    ->ArgNames({"patch", "basis", "roi"})
    ->Args({1, 0, 0})
    ->Args({1, 1, 0})
    ->Args({4, 1, 0})
    ->Args({8, 1, 0})
    ->Args({4, 0, 60})
    ->Args({4, 1, 60})
    ->Unit(benchmark::kMillisecond);

void BM_ArapFactor(benchmark::State& state) {
  const auto model = SheetModel(LaplacianWeights::kCotangent);
  const DeformationConstraints c = SheetConstraints(4);
  for (auto _ : state)
    if (!CheckSolver(state, ArapSolver::Create(model, c))) return;
}
BENCHMARK(BM_ArapFactor)->Unit(benchmark::kMillisecond)->Iterations(2);

// One ARAP round (local SVDs for every active vertex + one global
// back-substitution), warm-started from the previous round as in a drag session.
// Arg: ROI radius (0 = whole sheet).
void BM_ArapRound(benchmark::State& state) {
  const auto model = SheetModel(LaplacianWeights::kCotangent);
  const DeformationConstraints c = SheetConstraints(4, static_cast<int>(state.range(0)));
  const auto solver = ArapSolver::Create(model, c);
  if (!CheckSolver(state, solver)) return;
  std::vector<double> positions(3 * model->vertex_count());
  ArapOptions options;
  options.max_iterations = 1;
  options.tolerance = 0;
  const std::vector<double> targets = armature_bench::SheetDragTargets(c, 50);
  if (!solver->Solve(targets, options, positions).ok()) state.SkipWithError("ARAP failed");
  options.warm_start = true;
  for (auto _ : state) {
    auto report = solver->Solve(targets, options, positions);
    benchmark::DoNotOptimize(positions.data());
    if (!report.ok()) state.SkipWithError(report.status().message().c_str());
  }
}
BENCHMARK(BM_ArapRound)->ArgName("roi")->Arg(0)->Arg(60)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace armature
