// IK solvers on random reachable targets (forward kinematics of random poses
// within the limits, from the rest pose): success rate (within 1e-3 × chain
// length and 1e-3 rad) and median time per solve, request validation
// included. The same rigs against Orocos KDL are in ik_kdl_bench.cc.
#include <random>

#include "ik_bench_util.h"

namespace armature {
namespace {

using ik_rigs::LimbCase;

void Run(benchmark::State& state, const LimbCase& c, const std::function<void(IkRequest&)>& adjust) {
  const std::vector<ik_rigs::Target> targets = ik_bench::ReachableTargets(c, ik_bench::kTargets, 77);
  ik_bench::SolveStats stats;
  for (auto _ : state) stats = ik_bench::MeasureArmature(c, targets, adjust);
  ik_bench::Report(state, "", stats);
  state.SetLabel(c.name);
}

void BM_IkDls(benchmark::State& state, const char* name) { Run(state, ik_rigs::StandardCase(name), {}); }

// DLS, then settling on the solution nearest the start pose.
void BM_IkDlsRegularized(benchmark::State& state, const char* name) {
  Run(state, ik_rigs::StandardCase(name), [](IkRequest& r) { r.options.regularization = 1.0; });
}

void BM_IkChain(benchmark::State& state, const char* name, IkSolver solver) {
  Run(state, ik_rigs::StandardCase(name), [solver](IkRequest& r) { r.solver = solver; });
}

// Analytic: no limits, the chain is the effector's parent and grandparent.
void BM_IkTwoBone(benchmark::State& state, const char* name) {
  Run(state, ik_rigs::StandardCase(name), [](IkRequest& r) {
    r.solver = IkSolver::kTwoBone;
    r.limits.clear();
    r.root.clear();
  });
}

BENCHMARK_CAPTURE(BM_IkDls, cmu_left_arm_reach, "cmu_left_arm_reach")->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_IkDls, cmu_left_arm_pose, "cmu_left_arm_pose")->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_IkDls, cmu_right_leg_reach, "cmu_right_leg_reach")->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_IkDls, cmu_right_leg_pose, "cmu_right_leg_pose")->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_IkDls, seven_dof_pose, "seven_dof_pose")->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_IkDlsRegularized, cmu_left_arm_pose, "cmu_left_arm_pose")
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_IkChain, ccd_cmu_left_arm_reach, "cmu_left_arm_reach", IkSolver::kCcd)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_IkChain, fabrik_cmu_left_arm_reach, "cmu_left_arm_reach", IkSolver::kFabrik)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_IkTwoBone, cmu_left_arm_reach, "cmu_left_arm_reach")->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_IkTwoBone, cmu_right_leg_reach, "cmu_right_leg_reach")
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

// Both hands at once through spine and arms (13 free joints, 2 effectors).
void BM_IkDlsTwoHands(benchmark::State& state) {
  const LimbCase body = ik_rigs::UpperBodyCase();
  std::mt19937_64 rng(5);
  std::vector<IkRequest> requests;
  for (int i = 0; i < ik_bench::kTargets; ++i)
    requests.push_back(ik_rigs::TwoHandsRequest(body, ik_rigs::RandomPose(body, rng), 0.5e-3 * 8.5));  // arm ≈ 8.5
  ik_bench::SolveStats stats;
  for (auto _ : state) stats = ik_bench::MeasureRequests(body.skeleton, requests);
  ik_bench::Report(state, "", stats);
}
BENCHMARK(BM_IkDlsTwoHands)->Iterations(1)->Unit(benchmark::kMillisecond);

// Look-at for a head, with an up hint.
void BM_IkAim(benchmark::State& state) {
  const Skeleton s = ik_rigs::CmuLikeSkeleton();
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  std::vector<IkRequest> requests;
  for (int i = 0; i < ik_bench::kTargets; ++i) {
    requests.push_back(ik_rigs::OneEffector(IkSolver::kAim, "Head", Eigen::Vector3d(u(rng), 20.0 + u(rng), u(rng))));
    requests.back().effectors[0].up_hint = Eigen::Vector3d::UnitY();
  }
  ik_bench::SolveStats stats;
  for (auto _ : state) stats = ik_bench::MeasureRequests(s, requests);
  ik_bench::Report(state, "", stats);
}
BENCHMARK(BM_IkAim)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace armature
