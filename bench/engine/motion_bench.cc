// Motion blending cost on RobotExpressive (../shared/data; skipped when
// absent): a 3-layer motion (Walking and Running overrides in PHASE sync, and
// Wave masked to the right arm) against sampling one clip, per pose and per
// joint, in the same run. BM_MotionBlendRatio times both alternately in one
// loop and reports their ratio (the goal: 3 layers at most 2.5x one clip).
// Both sample the clips' runtime form (CompressClip at the default bound, with
// a context) and write a double local pose, as the server does: one clip by
// ClipSamplingJob, the blend its override layers by ClipSamplingFloatJob
// into float lanes (the float-lane blend, FloatBlendPlan in motion.h).
#include <ctime>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/anim/motion.h"
#include "armature/engine/io/gltf/gltf.h"

namespace armature {
namespace {

struct Robot {
  std::shared_ptr<const CompressedClip> walking, running, wave;
  MotionPlan three_layers;
  bool ok = false;
};

const Robot& LoadRobot() {
  static const Robot robot = [] {
    Robot r;
    std::ifstream in(ARMATURE_SHARED_DATA "/gltf/RobotExpressive/RobotExpressive.glb", std::ios::binary);
    if (!in) return r;
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto asset = ParseGltf(bytes, true, "robot");
    if (!asset.ok()) return r;
    for (const NamedClip& c : asset->clips) {
      auto compressed = CompressClip(c.clip);
      if (!compressed.ok()) return r;
      if (c.name == "robot.Walking") r.walking = *compressed;
      if (c.name == "robot.Running") r.running = *compressed;
      if (c.name == "robot.Wave") r.wave = *compressed;
    }
    if (!r.walking || !r.running || !r.wave) return r;
    Motion m;
    m.sync = TimeSync::kPhase;
    m.layers.resize(3);
    m.layers[0] = {r.walking, "Walking", 0.6};
    m.layers[1] = {r.running, "Running", 0.4};
    m.layers[2] = {r.wave, "Wave", 1.0};
    m.layers[2].mask = {{"ShoulderR", 1.0}};
    auto plan = BindMotion(m);
    if (!plan.ok()) return r;
    r.three_layers = std::move(*plan);
    r.ok = true;
    return r;
  }();
  return robot;
}

constexpr double kStep = 1.0 / 60;  // times swept across the clips

// The time column is per pose; `joints` gives the per-joint figure
// (BM_MotionBlendRatio reports both per pose and per joint).
void SetJoints(benchmark::State& state, size_t joints) { state.counters["joints"] = static_cast<double>(joints); }

// This thread's CPU time: the machine is shared, so wall time would count other processes.
double ThreadCpuNs() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e9 + static_cast<double>(ts.tv_nsec);
}

void BM_SampleOneClip(benchmark::State& state) {
  const Robot& r = LoadRobot();
  if (!r.ok) return state.SkipWithError("shared data gltf/RobotExpressive/RobotExpressive.glb is absent");
  std::vector<Trs> out(r.walking->skeleton->size());
  ClipSamplingContext context(*r.walking);
  double t = 0;
  for (auto _ : state) {
    if (!ClipSamplingJob{r.walking.get(), t, WrapMode::kLoop, &context, out, {}}.Run().ok())
      return state.SkipWithError("sampling failed");
    benchmark::DoNotOptimize(out.data());
    t += kStep;
  }
  SetJoints(state, out.size());
}
BENCHMARK(BM_SampleOneClip);

// One clip into float lanes (ClipSamplingFloatJob, as the blend samples its
// override layers): no double transforms, for comparison with BM_SampleOneClip.
void BM_SampleOneClipFloat(benchmark::State& state) {
  const Robot& r = LoadRobot();
  if (!r.ok) return state.SkipWithError("shared data gltf/RobotExpressive/RobotExpressive.glb is absent");
  const size_t n = r.walking->skeleton->size();
  std::vector<float> lanes(10 * n);
  FloatPose pose{std::span<float>(lanes).subspan(0, 4 * n), std::span<float>(lanes).subspan(4 * n, 3 * n),
                 std::span<float>(lanes).subspan(7 * n, 3 * n)};
  ClipSamplingContext context(*r.walking);
  double t = 0;
  for (auto _ : state) {
    if (!ClipSamplingFloatJob{r.walking.get(), t, WrapMode::kLoop, &context, pose}.Run().ok())
      return state.SkipWithError("sampling failed");
    benchmark::DoNotOptimize(lanes.data());
    t += kStep;
  }
  SetJoints(state, n);
}
BENCHMARK(BM_SampleOneClipFloat);

void BM_BlendThreeLayers(benchmark::State& state) {
  const Robot& r = LoadRobot();
  if (!r.ok) return state.SkipWithError("shared data gltf/RobotExpressive/RobotExpressive.glb is absent");
  std::vector<Trs> out(r.three_layers.skeleton->size());
  MotionWorkspace ws;
  ws.Resize(r.three_layers);
  double t = 0;
  for (auto _ : state) {
    if (!BlendMotionJob{&r.three_layers, t, &ws, out}.Run().ok()) return state.SkipWithError("blend failed");
    benchmark::DoNotOptimize(out.data());
    t += kStep;
  }
  SetJoints(state, out.size());
}
BENCHMARK(BM_BlendThreeLayers);

// Both in one loop, 64 poses each per iteration, timed apart in thread CPU
// time: the ratio is taken under the same conditions.
void BM_MotionBlendRatio(benchmark::State& state) {
  const Robot& r = LoadRobot();
  if (!r.ok) return state.SkipWithError("shared data gltf/RobotExpressive/RobotExpressive.glb is absent");
  std::vector<Trs> out(r.three_layers.skeleton->size());
  MotionWorkspace ws;
  ws.Resize(r.three_layers);
  ClipSamplingContext context(*r.walking);
  double one = 0, three = 0;  // CPU ns
  double t = 0;
  constexpr int kPoses = 64;
  for (auto _ : state) {
    const double a = ThreadCpuNs();
    for (int i = 0; i < kPoses; ++i) {
      (void)ClipSamplingJob{r.walking.get(), t + i * kStep, WrapMode::kLoop, &context, out, {}}.Run();
      benchmark::DoNotOptimize(out.data());
    }
    const double b = ThreadCpuNs();
    for (int i = 0; i < kPoses; ++i) {
      (void)BlendMotionJob{&r.three_layers, t + i * kStep, &ws, out}.Run();
      benchmark::DoNotOptimize(out.data());
    }
    three += ThreadCpuNs() - b;
    one += b - a;
    t += kPoses * kStep;
  }
  const double poses = static_cast<double>(state.iterations()) * kPoses;
  const double one_ns = one / poses, three_ns = three / poses;
  state.counters["one_clip_ns_per_pose"] = one_ns;
  state.counters["three_layers_ns_per_pose"] = three_ns;
  state.counters["one_clip_ns_per_joint"] = one_ns / static_cast<double>(out.size());
  state.counters["three_layers_ns_per_joint"] = three_ns / static_cast<double>(out.size());
  state.counters["ratio"] = three_ns / one_ns;
}
BENCHMARK(BM_MotionBlendRatio);

}  // namespace
}  // namespace armature
