// BVH parse throughput and per-pose sampling + FK cost. Baselines in the
// same run: from_chars over every token of the same bytes (the least any
// text parser must do), and ComputeWorld alone (FK without sampling).
#include <charconv>
#include <optional>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/demo_walk.h"
#include "armature/engine/kinematics/fk.h"
#include "bvh_bench_texts.h"

namespace armature {
namespace {

const std::optional<std::string>& CmuText() { return armature_bench::CmuBvhText(); }

void ParseBench(benchmark::State& state, const std::string& text) {
  for (auto _ : state) {
    StatusOr<BvhData> d = ParseBvh(text);
    if (!d.ok()) {
      state.SkipWithError(d.status().message().c_str());
      return;
    }
    benchmark::DoNotOptimize(d);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * text.size()));
  state.counters["bytes"] = static_cast<double>(text.size());
}

// Baseline: split on whitespace and from_chars each token, nothing else.
void TokenBaseline(benchmark::State& state, const std::string& text) {
  for (auto _ : state) {
    double sum = 0;
    const char* p = text.data();
    const char* end = p + text.size();
    while (p < end) {
      while (p < end && (*p == ' ' || *p == '\n' || *p == '\t' || *p == '\r')) ++p;
      const char* start = p;
      while (p < end && !(*p == ' ' || *p == '\n' || *p == '\t' || *p == '\r')) ++p;
      double v = 0;
      if (std::from_chars(start, p, v).ec == std::errc()) sum += v;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * text.size()));
}

// The CMU file's text, or null after marking the benchmark skipped.
const std::string* CmuTextOrSkip(benchmark::State& state) {
  if (!CmuText()) state.SkipWithError("shared data bvh/cmu_01_01.bvh is absent");
  return CmuText() ? &*CmuText() : nullptr;
}

// BM_BvhParse_Armature/<file>: ParseBvh's throughput (bytes_per_second);
// BM_BvhParse_Assimp (bvh_assimp_bench.cc) reads the same bytes.
void BM_BvhParse_Armature(benchmark::State& state, const std::string* (*text)(benchmark::State&)) {
  if (const std::string* t = text(state)) ParseBench(state, *t);
}
const std::string* LargeWalkText(benchmark::State&) { return &armature_bench::LargeWalkBvhText(); }
BENCHMARK_CAPTURE(BM_BvhParse_Armature, cmu_01_01, CmuTextOrSkip)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BvhParse_Armature, walk_16MB, LargeWalkText)->Unit(benchmark::kMillisecond);

void BM_BvhTokenBaseline(benchmark::State& state, const std::string* (*text)(benchmark::State&)) {
  if (const std::string* t = text(state)) TokenBaseline(state, *t);
}
BENCHMARK_CAPTURE(BM_BvhTokenBaseline, cmu_01_01, CmuTextOrSkip)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BvhTokenBaseline, walk_16MB, LargeWalkText)->Unit(benchmark::kMillisecond);

// One pose: SampleClip at a moving time, then ComputeWorld. arg 0 = the
// tracks' own interpolation (LINEAR for BVH), 1 = CUBIC (squad) override.
void SampleFkBench(benchmark::State& state, const BvhData& d, bool sample) {
  const Skeleton& sk = *d.skeleton;
  std::vector<Trs> local(sk.size());
  std::vector<Eigen::Affine3d> world(sk.size());
  SampleOptions options;
  options.wrap = WrapMode::kLoop;
  if (state.range(0) == 1) options.interpolation = Interpolation::kCubic;
  (void)SampleClip(*d.clip, 0.0, options, local);
  double t = 0;
  const double step = 0.0123;  // not a multiple of the frame time: interpolates
  for (auto _ : state) {
    if (sample) {
      if (!SampleClip(*d.clip, t, options, local).ok()) {
        state.SkipWithError("SampleClip failed");
        return;
      }
      t += step;
    }
    ComputeWorld(sk, local, world);
    benchmark::DoNotOptimize(world.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["joints"] = static_cast<double>(sk.size());
}

const std::optional<BvhData>& CmuData() {
  static const std::optional<BvhData> data = []() -> std::optional<BvhData> {
    if (!CmuText()) return std::nullopt;
    StatusOr<BvhData> d = ParseBvh(*CmuText());
    if (!d.ok()) return std::nullopt;
    return *d;
  }();
  return data;
}

const BvhData& DemoData() {
  static const BvhData data = MakeDemoWalk();
  return data;
}

void BM_SampleFk_Cmu(benchmark::State& state) {
  if (CmuTextOrSkip(state) && CmuData()) SampleFkBench(state, *CmuData(), true);
}
BENCHMARK(BM_SampleFk_Cmu)->Arg(0)->Arg(1);

void BM_FkOnly_Cmu(benchmark::State& state) {
  if (CmuTextOrSkip(state) && CmuData()) SampleFkBench(state, *CmuData(), false);
}
BENCHMARK(BM_FkOnly_Cmu)->Arg(0);

void BM_SampleFk_DemoWalk(benchmark::State& state) { SampleFkBench(state, DemoData(), true); }
BENCHMARK(BM_SampleFk_DemoWalk)->Arg(0)->Arg(1);

void BM_FkOnly_DemoWalk(benchmark::State& state) { SampleFkBench(state, DemoData(), false); }
BENCHMARK(BM_FkOnly_DemoWalk)->Arg(0);

}  // namespace
}  // namespace armature
