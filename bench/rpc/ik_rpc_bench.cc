// Inverse kinematics over a real gRPC connection: SolveIk round trips and
// IK session updates, with the empty RPC (BM_EmptyRpc_HealthCheck in
// evaluate_rpc_bench.cc, same server, same run) as the baseline: report the
// ratios. Targets are the wrist (and ankle) where the clip has them 0.1 s
// after the start pose, so each solve does a few real iterations.
#include <benchmark/benchmark.h>

#include "rpc_bench_server.h"

namespace {

using armature_bench::Server;
namespace v1 = armature::v1;

void AddEffector(v1::SolveIkRequest& r, const std::string& clip, const std::string& joint, double time) {
  v1::EvaluateClipRequest e;
  e.set_clip(clip);
  e.add_times(time);
  e.set_space(v1::WORLD);
  e.add_joints(joint);
  const auto world = Server().client->EvaluateClip(e);
  v1::IkEffector* effector = r.add_effectors();
  effector->set_joint(joint);
  for (int k = 0; k < 3; ++k) effector->add_target_position(world.poses(0).translations(k));
}

// Starts from `clip` at 1.0 s; targets from 1.1 s (or 1.0 s: already reached).
v1::SolveIkRequest Request(const std::string& clip, const std::vector<std::string>& joints, double target_time = 1.1) {
  v1::SolveIkRequest r;
  r.set_skeleton(clip);
  r.mutable_from_clip()->set_clip(clip);
  r.mutable_from_clip()->set_time(1.0);
  for (const auto& j : joints) AddEffector(r, clip, j, target_time);
  return r;
}

void Solve(benchmark::State& state, const v1::SolveIkRequest& r) {
  int iterations = 0;
  for (auto _ : state) {
    const auto answer = Server().client->SolveIk(r);
    if (!answer.converged()) return state.SkipWithError("did not converge");
    iterations = answer.iterations();
  }
  state.counters["ik_iterations"] = iterations;
}

void BM_SolveIk_DemoWalk_AlreadyReached(benchmark::State& state) {
  Solve(state, Request("demo_walk", {"LeftWrist"}, 1.0));
}
BENCHMARK(BM_SolveIk_DemoWalk_AlreadyReached)->UseRealTime();

void BM_SolveIk_DemoWalk_Dls_OneEffector(benchmark::State& state) { Solve(state, Request("demo_walk", {"LeftWrist"})); }
BENCHMARK(BM_SolveIk_DemoWalk_Dls_OneEffector)->UseRealTime();

void BM_SolveIk_DemoWalk_Dls_TwoEffectors(benchmark::State& state) {
  Solve(state, Request("demo_walk", {"LeftWrist", "RightAnkle"}));
}
BENCHMARK(BM_SolveIk_DemoWalk_Dls_TwoEffectors)->UseRealTime();

void BM_SolveIk_DemoWalk_TwoBone(benchmark::State& state) {
  v1::SolveIkRequest r = Request("demo_walk", {"RightAnkle"});
  r.set_solver(v1::TWO_BONE);
  Solve(state, r);
}
BENCHMARK(BM_SolveIk_DemoWalk_TwoBone)->UseRealTime();

void BM_SolveIk_Cmu_Dls_TwoEffectors(benchmark::State& state) {
  if (!Server().has_cmu) return state.SkipWithError("../shared/data/bvh/cmu_01_01.bvh not present");
  Solve(state, Request("cmu", {"LeftHand", "RightFoot"}));
}
BENCHMARK(BM_SolveIk_Cmu_Dls_TwoEffectors)->UseRealTime();

// One session, the wrist target moving 2.8 mm per update (a drag), the ankle pinned.
void BM_IkSession_Update_DemoWalk(benchmark::State& state) {
  const v1::SolveIkRequest start = Request("demo_walk", {"LeftWrist", "RightAnkle"}, 1.0);
  auto session = Server().client->OpenIkSession(start);
  const auto& p = start.effectors(0).target_position();
  int step = 0;
  int64_t iterations = 0;
  for (auto _ : state) {
    const int k = step++ % 200;
    const double offset = 0.2 * (k < 100 ? k : 200 - k);  // back and forth along a 28 cm line
    const auto& answer = session->MoveTarget(0, p[0] + offset, p[1], p[2] + offset);
    if (!answer.converged()) return state.SkipWithError("did not converge");
    iterations += answer.iterations();
  }
  session->Close();
  state.counters["ik_iterations"] =
      benchmark::Counter(static_cast<double>(iterations), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_IkSession_Update_DemoWalk)->UseRealTime();

}  // namespace
