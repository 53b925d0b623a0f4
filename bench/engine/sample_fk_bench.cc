// Sampling plus local-to-world per pose on the CMU clip (../shared/data;
// skipped when absent, 31 joints, 2,752 keys per track), the figure issue 15
// compares with ozz: the runtime form (CompressClip at the default bound,
// ClipSamplingJob with a context, then ComputeWorld) and, in the same run, the pipeline before it (SampleClip,
// then ComputeWorldBefore, the old FK kept here) as the reference. Each reports
// ns per joint (`per_joint`); BM_SampleFk_Memory{,_RobotExpressive} report
// the file form's bytes per key and the runtime form's per joint-sample.
#include <fstream>
#include <memory>
#include <iterator>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/io/asset.h"
#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/kinematics/fk.h"

namespace armature {
namespace {

struct Cmu {
  std::shared_ptr<const Clip> clip;
  std::shared_ptr<const CompressedClip> compiled;
};

const Cmu& LoadCmu() {
  static const Cmu cmu = [] {
    Cmu c;
    std::ifstream in(ARMATURE_SHARED_DATA "/bvh/cmu_01_01.bvh", std::ios::binary);
    if (!in) return c;
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto bvh = ParseBvh(text);
    if (!bvh.ok()) return c;
    auto compiled = CompressClip(bvh->clip);
    if (!compiled.ok()) return c;
    c.clip = bvh->clip;
    c.compiled = *compiled;
    return c;
  }();
  return cmu;
}

// ComputeWorld as it was before the runtime form (Trs::ToAffine and Eigen's
// affine product per joint), so the file-form benchmarks time the old pipeline.
void ComputeWorldBefore(const Skeleton& skeleton, std::span<const Trs> local, std::span<Eigen::Affine3d> world) {
  for (size_t i = 0; i < skeleton.size(); ++i) {
    const Eigen::Affine3d m = local[i].ToAffine();
    const int p = skeleton.parents[i];
    world[i] = p < 0 ? m : world[static_cast<size_t>(p)] * m;
  }
}

enum class Form { kFile, kCompiled };
enum class Times { kSequential, kRandom, kNone };

// Sample + FK over `times`: t += 1/60 s wrapping at the end, or uniformly
// random times (precomputed, so the generator is not timed); kNone: FK only.
void SampleFk(benchmark::State& state, Form form, Times times, Interpolation interpolation) {
  const Cmu& cmu = LoadCmu();
  if (!cmu.clip) {
    state.SkipWithError("shared data bvh/cmu_01_01.bvh is absent");
    return;
  }
  const Skeleton& sk = *cmu.clip->skeleton;
  std::vector<Trs> local(sk.size());
  std::vector<Eigen::Affine3d> world(sk.size());
  std::vector<double> random(4096);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> any(0, cmu.clip->duration);
  for (double& t : random) t = any(rng);
  const SampleOptions options{.interpolation = interpolation, .wrap = WrapMode::kLoop};
  double t = 1;
  size_t i = 0;
  ClipSamplingContext context(*cmu.compiled);
  ClipSamplingJob job{cmu.compiled.get(), 0, WrapMode::kLoop, &context, local, interpolation};
  for (auto _ : state) {
    if (times != Times::kNone || i++ == 0) {
      const double at = times == Times::kRandom ? random[i++ & 4095] : t;
      job.time = at;
      const Status s = form == Form::kFile ? SampleClip(*cmu.clip, at, options, local) : job.Run();
      if (!s.ok()) state.SkipWithError(s.message().c_str());
    }
    if (form == Form::kFile)
      ComputeWorldBefore(sk, local, world);
    else
      ComputeWorld(sk, local, world);
    benchmark::DoNotOptimize(world.data());
    benchmark::ClobberMemory();
    t += 1.0 / 60;
  }
  state.counters["per_joint"] = benchmark::Counter(static_cast<double>(state.iterations() * sk.size()),
                                                   benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_SampleFk_Sequential(benchmark::State& s) {
  SampleFk(s, Form::kCompiled, Times::kSequential, Interpolation::kLinear);
}
void BM_SampleFk_Sequential_FileForm(benchmark::State& s) {
  SampleFk(s, Form::kFile, Times::kSequential, Interpolation::kLinear);
}
void BM_SampleFk_RandomSeek(benchmark::State& s) {
  SampleFk(s, Form::kCompiled, Times::kRandom, Interpolation::kLinear);
}
void BM_SampleFk_RandomSeek_FileForm(benchmark::State& s) {
  SampleFk(s, Form::kFile, Times::kRandom, Interpolation::kLinear);
}
void BM_SampleFk_Cubic(benchmark::State& s) { SampleFk(s, Form::kCompiled, Times::kSequential, Interpolation::kCubic); }
void BM_SampleFk_Cubic_FileForm(benchmark::State& s) {
  SampleFk(s, Form::kFile, Times::kSequential, Interpolation::kCubic);
}
BENCHMARK(BM_SampleFk_Sequential);
BENCHMARK(BM_SampleFk_Sequential_FileForm);
BENCHMARK(BM_SampleFk_RandomSeek);
BENCHMARK(BM_SampleFk_RandomSeek_FileForm);
BENCHMARK(BM_SampleFk_Cubic);
BENCHMARK(BM_SampleFk_Cubic_FileForm);

// The hierarchy alone (ozz's LocalToModelJob is the counterpart), now and
// before, on the pose at 1 s.
void BM_SampleFk_HierarchyOnly(benchmark::State& s) {
  SampleFk(s, Form::kCompiled, Times::kNone, Interpolation::kLinear);
}
void BM_SampleFk_HierarchyOnly_Before(benchmark::State& s) {
  SampleFk(s, Form::kFile, Times::kNone, Interpolation::kLinear);
}
BENCHMARK(BM_SampleFk_HierarchyOnly);
BENCHMARK(BM_SampleFk_HierarchyOnly_Before);

// Bytes of the animated tracks: the file form's std::vector keys (a double
// time and the value per key) per key, and the runtime form's ByteSize() at
// the default bound per joint-sample (joints × frames), over every clip of
// the file. The server holds the runtime form (and, until the file form
// leaves memory, both).
void ReportMemory(benchmark::State& state, const std::vector<std::shared_ptr<const Clip>>& clips) {
  size_t keys = 0, file_bytes = 0, runtime_bytes = 0, joint_samples = 0;
  for (const std::shared_ptr<const Clip>& clip : clips) {
    for (const JointTrack& jt : clip->joints) {
      keys += jt.rotation.times.size() + jt.translation.times.size() + jt.scale.times.size();
      file_bytes += jt.rotation.times.size() * (sizeof(double) + sizeof(Eigen::Quaterniond)) +
                    (jt.translation.times.size() + jt.scale.times.size()) * (sizeof(double) + sizeof(Eigen::Vector3d));
    }
    auto compressed = CompressClip(clip);
    if (!compressed.ok()) return state.SkipWithError(compressed.status().message().c_str());
    runtime_bytes += (*compressed)->ByteSize();
    joint_samples += clip->skeleton->size() * (*compressed)->frames.count;
  }
  for (auto _ : state) benchmark::DoNotOptimize(keys);
  const auto per_key = [&](size_t bytes) { return static_cast<double>(bytes) / static_cast<double>(keys); };
  state.counters["clips"] = static_cast<double>(clips.size());
  state.counters["keys"] = static_cast<double>(keys);
  state.counters["file_bytes_per_key"] = per_key(file_bytes);
  state.counters["runtime_bytes_per_joint_sample"] =
      static_cast<double>(runtime_bytes) / static_cast<double>(joint_samples);
}

void BM_SampleFk_Memory(benchmark::State& state) {
  const Cmu& cmu = LoadCmu();
  if (!cmu.clip) {
    state.SkipWithError("shared data bvh/cmu_01_01.bvh is absent");
    return;
  }
  ReportMemory(state, {cmu.clip});
}
BENCHMARK(BM_SampleFk_Memory)->Iterations(1);

// The same over RobotExpressive's clips (glTF, resampled or not as imported).
void BM_SampleFk_Memory_RobotExpressive(benchmark::State& state) {
  std::ifstream in(ARMATURE_SHARED_DATA "/gltf/RobotExpressive/RobotExpressive.glb", std::ios::binary);
  if (!in) return state.SkipWithError("shared data gltf/RobotExpressive/RobotExpressive.glb is absent");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto contents = ParseAsset(AssetFormat::kGlb, bytes, "robot");
  if (!contents.ok()) return state.SkipWithError(contents.status().message().c_str());
  std::vector<std::shared_ptr<const Clip>> clips;
  for (const NamedClip& c : contents->clips) clips.push_back(c.clip);
  ReportMemory(state, clips);
}
BENCHMARK(BM_SampleFk_Memory_RobotExpressive)->Iterations(1);

}  // namespace
}  // namespace armature
