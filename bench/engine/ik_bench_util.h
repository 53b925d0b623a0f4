// Shared by the IK benchmarks: reachable targets on the test rigs, and
// success rate / median time of solving them one by one.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "../../tests/engine/testing/ik_rigs.h"
#include "armature/engine/kinematics/ik.h"

namespace armature::ik_bench {

inline constexpr int kTargets = 1000;

inline std::vector<ik_rigs::Target> ReachableTargets(const ik_rigs::LimbCase& c, int n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<ik_rigs::Target> targets;
  for (int i = 0; i < n; ++i) targets.push_back(ik_rigs::TargetOf(c, ik_rigs::RandomPose(c, rng)));
  return targets;
}

struct SolveStats {
  double success_percent = 0;
  double median_us = 0;
  double p90_us = 0;
  double mean_iterations = 0;
};

// Times `solve(i)` for each target; `solve` returns {reached, iterations}.
template <class Solve>
SolveStats Measure(int n, Solve&& solve) {
  std::vector<double> times;
  int reached = 0;
  double iterations = 0;
  for (int i = 0; i < n; ++i) {
    const auto start = std::chrono::steady_clock::now();
    const std::pair<bool, int> r = solve(i);
    times.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
    reached += r.first;
    iterations += r.second;
  }
  std::sort(times.begin(), times.end());
  return {100.0 * reached / n, times[times.size() / 2], times[times.size() * 9 / 10], iterations / n};
}

// Armature's solver from the rest pose, on requests built (and adjusted by
// `adjust`) before timing.
inline SolveStats MeasureArmature(const ik_rigs::LimbCase& c, const std::vector<ik_rigs::Target>& targets,
                                  const std::function<void(IkRequest&)>& adjust = {}) {
  std::vector<IkRequest> requests;
  for (const ik_rigs::Target& t : targets) {
    requests.push_back(ik_rigs::RequestFor(c, t));
    if (adjust) adjust(requests.back());
  }
  IkWorkspace ws;
  IkResult result;
  return Measure(static_cast<int>(targets.size()), [&](int i) {
    if (!SolveIk(c.skeleton, requests[i], ws, result).ok()) return std::pair(false, 0);
    const IkEffectorResidual& r = result.residuals[0];
    return std::pair(ik_rigs::Reached(c, r.position_error, r.rotation_error), result.iterations);
  });
}

// Prepared requests on `skeleton`, success = converged.
inline SolveStats MeasureRequests(const Skeleton& skeleton, const std::vector<IkRequest>& requests) {
  IkWorkspace ws;
  IkResult result;
  return Measure(static_cast<int>(requests.size()), [&](int i) {
    return std::pair(SolveIk(skeleton, requests[i], ws, result).ok() && result.converged, result.iterations);
  });
}

inline void Report(benchmark::State& state, const std::string& prefix, const SolveStats& s) {
  state.counters[prefix + "success_%"] = s.success_percent;
  state.counters[prefix + "median_us"] = s.median_us;
  state.counters[prefix + "p90_us"] = s.p90_us;
  state.counters[prefix + "iterations"] = s.mean_iterations;
}

}  // namespace armature::ik_bench
