// The crowd's server CPU per character-tick (issue 31, target ≤ 1.0 µs for 31
// joints) on CMU 01_01 (../shared/data; skipped when absent): CrowdTicker
// sampling with ClipSamplingJob and encoding every character each tick,
// without sharing (each character at its own clip time) and with sharing
// (clip times rounded to 1/120 s: characters on 50 distinct offsets). Reports
// ns per character-tick (`per_character`) and the samples taken a tick.
// mixed:1 spreads the characters as armature-load does (offsets over 10 s,
// speeds 0.8–1.2): each tick then seeks all over the clip.
#include <cmath>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/anim/crowd/crowd_ticker.h"
#include "armature/engine/io/bvh/bvh.h"

namespace armature {
namespace {

std::shared_ptr<const CompressedClip> CrowdCmu() {
  static const std::shared_ptr<const CompressedClip> clip = []() -> std::shared_ptr<const CompressedClip> {
    std::ifstream in(ARMATURE_SHARED_DATA "/bvh/cmu_01_01.bvh", std::ios::binary);
    if (!in) return nullptr;
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto bvh = ParseBvh(text);
    if (!bvh.ok()) return nullptr;
    auto compressed = CompressClip(bvh->clip);
    return compressed.ok() ? *compressed : nullptr;
  }();
  return clip;
}

// range(0): characters; range(1): 1 = sharing on (50 distinct offsets);
// range(2): 1 = mixed offsets and speeds (armature-load's crowd).
void BM_CrowdTick(benchmark::State& state) {
  const auto clip = CrowdCmu();
  if (!clip) return state.SkipWithError("../shared/data/bvh/cmu_01_01.bvh is absent");
  const bool sharing = state.range(1) != 0;
  CrowdTicker ticker({.budget_us = 1e9, .share_quantum = sharing ? 1.0 / 120 : 0});
  const uint32_t index = *ticker.AddClip(clip);
  const auto characters = static_cast<uint32_t>(state.range(0));
  const bool mixed = state.range(2) != 0;
  for (uint32_t id = 0; id < characters; ++id) {
    double offset = sharing ? 0.41 * (id % 50) : 0.0137 * id, speed = 1;
    if (mixed) offset = std::fmod(0.37 * id, 10.0), speed = 0.8 + 0.4 * (id % 7) / 6.0;
    if (!ticker.Add({.id = id, .clip = index, .time_offset = offset, .speed = speed, .significance = double(id)}).ok())
      return state.SkipWithError("add failed");
  }
  CrowdTick tick;
  uint64_t k = 0, updates = 0, samples = 0;
  for (auto _ : state) {
    if (!ticker.Tick(k, static_cast<double>(k) / 30, &tick).ok()) return state.SkipWithError("tick failed");
    ++k;
    updates += tick.ids.size();
    samples += tick.samples;
    benchmark::DoNotOptimize(tick.poses.data());
  }
  state.counters["per_character"] =
      benchmark::Counter(static_cast<double>(updates), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["samples_per_tick"] = static_cast<double>(samples) / static_cast<double>(k);
  state.counters["bytes_per_joint"] = static_cast<double>(ticker.layout(index).EncodedSize()) / 31;
}
BENCHMARK(BM_CrowdTick)
    ->ArgsProduct({{1000, 10000}, {0, 1}, {0, 1}})
    ->ArgNames({"characters", "sharing", "mixed"})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace armature
