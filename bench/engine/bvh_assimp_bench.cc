// BVH parse against assimp's BVH import (Debian libassimp-dev, a benchmark
// peer only) on the same bytes: BM_BvhParse_Assimp/<file> times assimp's
// ReadFileFromMemory (no post-processing) plus freeing its scene, and in the
// same iterations ParseBvh plus freeing its result, so both see the same
// machine load. Times are the thread's CPU time. Counters: MB/s of each and
// assimp_over_armature, assimp's time over ours (above 1: we are faster).
#include <ctime>
#include <string>

#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <benchmark/benchmark.h>

#include "armature/engine/io/bvh/bvh.h"
#include "bvh_bench_texts.h"

namespace {

double ThreadSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

void AssimpVsArmature(benchmark::State& state, const std::string& text) {
  Assimp::Importer importer;
  {
    const aiScene* scene = importer.ReadFileFromMemory(text.data(), text.size(), 0, "bvh");
    if (scene == nullptr || scene->mNumAnimations != 1)
      return state.SkipWithError(("assimp did not read the BVH: " + std::string(importer.GetErrorString())).c_str());
    importer.FreeScene();
    if (!armature::ParseBvh(text).ok()) return state.SkipWithError("ParseBvh failed");
  }
  double assimp_seconds = 0, armature_seconds = 0;
  for (auto _ : state) {
    double start = ThreadSeconds();
    benchmark::DoNotOptimize(importer.ReadFileFromMemory(text.data(), text.size(), 0, "bvh"));
    importer.FreeScene();
    const double assimp = ThreadSeconds() - start;
    state.SetIterationTime(assimp);
    assimp_seconds += assimp;
    start = ThreadSeconds();
    {
      auto parsed = armature::ParseBvh(text);
      benchmark::DoNotOptimize(parsed);
    }
    armature_seconds += ThreadSeconds() - start;
  }
  const double bytes = static_cast<double>(text.size()) * static_cast<double>(state.iterations());
  state.counters["assimp_MBps"] = bytes / assimp_seconds / 1e6;
  state.counters["armature_MBps"] = bytes / armature_seconds / 1e6;
  state.counters["assimp_over_armature"] = assimp_seconds / armature_seconds;
  state.counters["bytes"] = static_cast<double>(text.size());
}

void BM_BvhParse_Assimp_cmu_01_01(benchmark::State& state) {
  if (!armature_bench::CmuBvhText()) return state.SkipWithError("shared data bvh/cmu_01_01.bvh is absent");
  AssimpVsArmature(state, *armature_bench::CmuBvhText());
}
BENCHMARK(BM_BvhParse_Assimp_cmu_01_01)
    ->Name("BM_BvhParse_Assimp/cmu_01_01")
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

void BM_BvhParse_Assimp_walk_16MB(benchmark::State& state) {
  AssimpVsArmature(state, armature_bench::LargeWalkBvhText());
}
BENCHMARK(BM_BvhParse_Assimp_walk_16MB)
    ->Name("BM_BvhParse_Assimp/walk_16MB")
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
