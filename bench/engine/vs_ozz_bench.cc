// Armature against ozz-animation 0.16 in the same run (issue 15). Both sample
// the same motion, the CMU clip (../shared/data/bvh/cmu_01_01.bvh) parsed by
// our BVH reader and built as an ozz RawAnimation + RawSkeleton, and turn it
// into world (model) transforms: our ClipSamplingJob (on the clip's runtime
// form, compressed once in setup as the server does at import) + ComputeWorld
// against ozz's SamplingJob + LocalToModelJob. Both skin the skinning benchmark's cylinder
// (cylinder_rig.h, 16,384 vertices, 4 influences, normals): our LBS against
// ozz's SkinningJob. Pairs are BM_VsOzz_<what>_Armature / _Ozz (and
// RandomSeek_OzzIframes, ozz built with an iframe every 0.1 s; Fk, the
// hierarchy alone: our ComputeWorld, its AVX2 kernel on a CPU that has AVX2,
// against ozz's LocalToModelJob; Fk_ArmatureScalar, unpaired, is the scalar
// loop that runs without AVX2, with the same matrices bit for bit, and
// FkRotations_Armature{,Scalar} the same with world rotations, as
// EvaluateClip's world space asks);
// scripts/bench_ratios.py prints each pair's ratio after `make bench`.
//
// ozz is built only with -DARMATURE_BENCH_OZZ=ON (make bench) and the tarball
// in ../shared/third_party; otherwise the ozz halves skip, saying why. Setup
// checks that both libraries compute the same thing (world positions within
// kMaxRelativeError of the skeleton's size, skinned vertices within 1e-4) and
// aborts with a message when they do not, so a ratio never compares
// different work.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "armature/engine/anim/clip.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/kinematics/fk.h"
#include "armature/engine/mesh/skinning.h"
#include "cylinder_rig.h"

#if ARMATURE_HAVE_OZZ
#include "ozz/animation/offline/animation_builder.h"
#include "ozz/animation/offline/raw_animation.h"
#include "ozz/animation/offline/raw_skeleton.h"
#include "ozz/animation/offline/skeleton_builder.h"
#include "ozz/animation/runtime/animation.h"
#include "ozz/animation/runtime/local_to_model_job.h"
#include "ozz/animation/runtime/sampling_job.h"
#include "ozz/animation/runtime/skeleton.h"
#include "ozz/base/maths/simd_math.h"
#include "ozz/base/maths/soa_transform.h"
#include "ozz/geometry/runtime/skinning_job.h"
#endif

namespace armature {
namespace {

constexpr double kStep = 1.0 / 60;          // sequential playback
constexpr size_t kSeekTimes = 1024;         // random seek: a fixed pseudo-random sequence
constexpr double kMaxRelativeError = 1e-3;  // of the skeleton's size (ozz keeps half-float translations)
constexpr int kSkinRings = 256;             // 256 × 64 = 16,384 vertices

void Fail(const std::string& what) {
  std::fprintf(stderr, "vs_ozz_bench: %s\n", what.c_str());
  std::abort();
}

struct Cmu {
  std::shared_ptr<const Clip> clip;
  std::vector<double> seek_times;  // in [0, duration]
  std::string absent;              // why there is no clip
};

const Cmu& LoadCmu() {
  static const Cmu cmu = [] {
    Cmu c;
    std::ifstream in(std::string(ARMATURE_SHARED_DATA) + "/bvh/cmu_01_01.bvh", std::ios::binary);
    if (!in) {
      c.absent = "shared data bvh/cmu_01_01.bvh is absent";
      return c;
    }
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    StatusOr<BvhData> bvh = ParseBvh(text);
    if (!bvh.ok()) Fail("cmu_01_01.bvh does not parse: " + bvh.status().message());
    c.clip = bvh->clip;
    std::mt19937 rng(15);
    std::uniform_real_distribution<double> uniform(0, c.clip->duration);
    for (size_t i = 0; i < kSeekTimes; ++i) c.seek_times.push_back(uniform(rng));
    return c;
  }();
  return cmu;
}

void SetJoints(benchmark::State& state, size_t joints) {
  state.counters["joints"] = static_cast<double>(joints);
  // Seconds per joint (printed with an SI prefix: "47n" = 47 ns).
  state.counters["per_joint"] = benchmark::Counter(
      static_cast<double>(joints), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void SetVertices(benchmark::State& state, size_t vertices) {
  state.counters["vertices"] = static_cast<double>(vertices);
  state.counters["per_vertex"] = benchmark::Counter(
      static_cast<double>(vertices), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// The CMU clip's runtime form, compressed once at the default bound (the
// server compresses at import).
const CompressedClip& CompressedCmu(const std::shared_ptr<const Clip>& clip) {
  static const std::shared_ptr<const CompressedClip> compressed = [&] {
    StatusOr<std::shared_ptr<const CompressedClip>> c = CompressClip(clip);
    if (!c.ok()) Fail("CompressClip failed on the CMU clip: " + c.status().message());
    return *c;
  }();
  return *compressed;
}

// Our per-call state for a clip: the sampling job's context, local and world poses.
struct ArmaturePose {
  explicit ArmaturePose(const std::shared_ptr<const Clip>& c)
      : clip(*c),
        compressed(CompressedCmu(c)),
        context(compressed),
        local(c->skeleton->size()),
        world(c->skeleton->size()),
        world_rotation(c->skeleton->size()) {}
  bool Sample(double t) {  // as the server samples: the job, sequential playback through its context
    return ClipSamplingJob{&compressed, t, WrapMode::kClamp, &context, local, {}}.Run().ok();
  }
  void Fk() { ComputeWorld(*clip.skeleton, local, world); }
  void FkScalar() { ComputeWorldScalar(*clip.skeleton, local, world); }
  void FkRotations(bool scalar) {
    if (scalar)
      ComputeWorldScalar(*clip.skeleton, local, world, world_rotation);
    else
      ComputeWorld(*clip.skeleton, local, world, world_rotation);
  }
  const Clip& clip;
  const CompressedClip& compressed;
  ClipSamplingContext context;
  std::vector<Trs> local;
  std::vector<Eigen::Affine3d> world;
  std::vector<Eigen::Quaterniond> world_rotation;
};

// Our sampling + FK: one pose per iteration, at t += kStep (sequential) or
// at the next of the fixed random times (random seek).
void BM_VsOzz_SampleFk_Armature(benchmark::State& state, bool sequential) {
  const Cmu& cmu = LoadCmu();
  if (!cmu.clip) return state.SkipWithError(cmu.absent.c_str());
  ArmaturePose pose(cmu.clip);
  double t = 0;
  size_t i = 0;
  for (auto _ : state) {
    if (!sequential) t = cmu.seek_times[i++ % kSeekTimes];
    if (!pose.Sample(t)) return state.SkipWithError("sampling failed");
    pose.Fk();
    benchmark::DoNotOptimize(pose.world.data());
    benchmark::ClobberMemory();
    if (sequential && (t += kStep) > cmu.clip->duration) t -= cmu.clip->duration;
  }
  SetJoints(state, pose.world.size());
}

// The hierarchy alone: one pose (sampled once, at a third of the clip) to
// world, by ComputeWorld or (`scalar`) by the loop that runs without AVX2;
// with `rotations`, world rotations too.
void BM_VsOzz_Fk_Armature(benchmark::State& state, bool scalar, bool rotations) {
  const Cmu& cmu = LoadCmu();
  if (!cmu.clip) return state.SkipWithError(cmu.absent.c_str());
  ArmaturePose pose(cmu.clip);
  if (!pose.Sample(cmu.clip->duration / 3)) return state.SkipWithError("sampling failed");
  for (auto _ : state) {
    if (rotations)
      pose.FkRotations(scalar);
    else if (scalar)
      pose.FkScalar();
    else
      pose.Fk();
    benchmark::DoNotOptimize(pose.world.data());
    benchmark::ClobberMemory();
  }
  SetJoints(state, pose.world.size());
}

void BM_VsOzz_Skin_Armature(benchmark::State& state) {
  const armature_bench::CylinderRig& rig = armature_bench::MakeCylinderRig(kSkinRings, false);
  const size_t n = rig.mesh.vertex_count();
  std::vector<float> positions(3 * n), normals(3 * n);
  SkinningWorkspace ws;
  SkinningJob job;
  job.mesh = &rig.mesh;
  job.joint_world = rig.world;
  job.method = SkinningMethod::kLinear;
  job.parallel = false;
  job.positions = positions;
  job.normals = normals;
  job.workspace = &ws;
  for (auto _ : state) {
    if (!job.Run().ok()) return state.SkipWithError("skinning failed");
    benchmark::DoNotOptimize(positions.data());
    benchmark::ClobberMemory();
  }
  SetVertices(state, n);
}

#if ARMATURE_HAVE_OZZ

namespace oa = ozz::animation;
namespace om = ozz::math;

om::Float3 ToOzz(const Eigen::Vector3d& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}
om::Quaternion ToOzz(const Eigen::Quaterniond& q) {  // ozz's order is x, y, z, w
  return {static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()), static_cast<float>(q.w())};
}
om::Float4x4 ToOzz(const Eigen::Affine3d& a) {
  const Eigen::Matrix4d& m = a.matrix();
  om::Float4x4 out;
  for (int c = 0; c < 4; ++c)
    out.cols[c] = om::simd_float4::Load(static_cast<float>(m(0, c)), static_cast<float>(m(1, c)),
                                        static_cast<float>(m(2, c)), static_cast<float>(m(3, c)));
  return out;
}
Eigen::Vector3d Translation(const om::Float4x4& m) {
  float f[3];
  om::Store3PtrU(m.cols[3], f);
  return {f[0], f[1], f[2]};
}

// Our skeleton as an ozz RawSkeleton (a tree of joints with rest transforms).
oa::offline::RawSkeleton::Joint OzzJoint(const Skeleton& s, const std::vector<std::vector<int>>& children, int j) {
  oa::offline::RawSkeleton::Joint joint;
  joint.name = s.names[static_cast<size_t>(j)].c_str();
  const Trs& rest = s.rest[static_cast<size_t>(j)];
  joint.transform = {ToOzz(rest.translation), ToOzz(rest.rotation), ToOzz(rest.scale)};
  for (int c : children[static_cast<size_t>(j)]) joint.children.push_back(OzzJoint(s, children, c));
  return joint;
}

// A track's keys as ozz keys; an empty track (the joint has no such channel)
// becomes one key at the rest value, as ozz reads an empty track as identity.
template <class OzzKey, class V>
void CopyKeys(const Track<V>& track, const V& rest, ozz::vector<OzzKey>& out) {
  if (track.empty()) {
    out.push_back({0.f, ToOzz(rest)});
    return;
  }
  for (size_t k = 0; k < track.times.size(); ++k)
    out.push_back({static_cast<float>(track.times[k]), ToOzz(track.values[k])});
}

struct OzzCmu {
  ozz::unique_ptr<oa::Skeleton> skeleton;
  ozz::unique_ptr<oa::Animation> animation, animation_iframes;
  std::vector<int> ours;  // ozz joint → our joint
};

// ozz's per-call state: a sampling context (its cursor), SoA locals, model
// matrices, and the two jobs wired to them.
struct OzzPose {
  OzzPose(const oa::Skeleton& skeleton, const oa::Animation& animation)
      : context(skeleton.num_joints()),
        locals(static_cast<size_t>(skeleton.num_soa_joints())),
        models(static_cast<size_t>(skeleton.num_joints())) {
    sampling.animation = &animation;
    sampling.context = &context;
    sampling.output = ozz::make_span(locals);
    ltm.skeleton = &skeleton;
    ltm.input = ozz::make_span(locals);
    ltm.output = ozz::make_span(models);
  }
  bool Sample(float ratio) {
    sampling.ratio = ratio;
    return sampling.Run();
  }
  bool Fk() { return ltm.Run(); }
  oa::SamplingJob::Context context;
  ozz::vector<om::SoaTransform> locals;
  ozz::vector<om::Float4x4> models;
  oa::SamplingJob sampling;
  oa::LocalToModelJob ltm;
};

// Samples both at `time` and compares world positions; returns the largest
// difference relative to the pose's bounding-box diagonal, aborting above
// kMaxRelativeError.
double CheckAgreement(const std::shared_ptr<const Clip>& shared, const OzzCmu& o, const oa::Animation& animation,
                      double time) {
  const Clip& clip = *shared;
  ArmaturePose ours(shared);
  if (!ours.Sample(time)) Fail("ClipSamplingJob failed");
  ours.Fk();
  OzzPose theirs(*o.skeleton, animation);
  if (!theirs.Sample(static_cast<float>(time / clip.duration)) || !theirs.Fk())
    Fail("ozz SamplingJob or LocalToModelJob failed");
  const std::vector<Eigen::Affine3d>& world = ours.world;
  const ozz::vector<om::Float4x4>& models = theirs.models;
  Eigen::AlignedBox3d box;
  for (const Eigen::Affine3d& w : world) box.extend(w.translation());
  const double size = box.diagonal().norm();
  double worst = 0;
  for (size_t k = 0; k < models.size(); ++k) {
    const int j = o.ours[k];
    const double error = (Translation(models[k]) - world[static_cast<size_t>(j)].translation()).norm() / size;
    if (error > kMaxRelativeError) {
      char line[256];
      std::snprintf(line, sizeof line,
                    "ozz and Armature disagree at t=%.4f s on joint %s: %.3g of the skeleton's size %.3g", time,
                    clip.skeleton->names[static_cast<size_t>(j)].c_str(), error, size);
      Fail(line);
    }
    worst = std::max(worst, error);
  }
  return worst;
}

struct OzzCmuResult {
  OzzCmu ozz;
  double max_relative_error = 0;  // over the checked times, both animations
};

const OzzCmuResult& LoadOzzCmu() {
  static const OzzCmuResult result = [] {
    OzzCmuResult r;
    const Cmu& cmu = LoadCmu();
    if (!cmu.clip) return r;
    const Clip& clip = *cmu.clip;
    const Skeleton& s = *clip.skeleton;
    std::vector<std::vector<int>> children(s.size());
    oa::offline::RawSkeleton raw_skeleton;
    for (size_t j = 0; j < s.size(); ++j)
      if (s.parents[j] >= 0) children[static_cast<size_t>(s.parents[j])].push_back(static_cast<int>(j));
    for (size_t j = 0; j < s.size(); ++j)
      if (s.parents[j] < 0) raw_skeleton.roots.push_back(OzzJoint(s, children, static_cast<int>(j)));
    if (!raw_skeleton.Validate()) Fail("the CMU skeleton is not a valid ozz RawSkeleton");
    r.ozz.skeleton = oa::offline::SkeletonBuilder()(raw_skeleton);
    if (!r.ozz.skeleton) Fail("ozz SkeletonBuilder failed");
    // ozz orders joints depth first; map them back by name.
    for (const char* name : r.ozz.skeleton->joint_names()) r.ozz.ours.push_back(s.Find(name));
    if (std::count(r.ozz.ours.begin(), r.ozz.ours.end(), -1) > 0 || r.ozz.ours.size() != s.size())
      Fail("ozz skeleton joints do not map onto the CMU skeleton");

    oa::offline::RawAnimation raw;
    raw.duration = static_cast<float>(clip.duration);
    raw.tracks.resize(r.ozz.ours.size());
    for (size_t k = 0; k < r.ozz.ours.size(); ++k) {
      const auto j = static_cast<size_t>(r.ozz.ours[k]);
      CopyKeys(clip.joints[j].translation, s.rest[j].translation, raw.tracks[k].translations);
      CopyKeys(clip.joints[j].rotation, s.rest[j].rotation, raw.tracks[k].rotations);
      CopyKeys(clip.joints[j].scale, s.rest[j].scale, raw.tracks[k].scales);
    }
    if (!raw.Validate()) Fail("the CMU clip is not a valid ozz RawAnimation");
    oa::offline::AnimationBuilder builder;
    r.ozz.animation = builder(raw);
    builder.iframe_interval = 0.1f;
    r.ozz.animation_iframes = builder(raw);
    if (!r.ozz.animation || !r.ozz.animation_iframes) Fail("ozz AnimationBuilder failed");

    // Key times, times between keys, both ends.
    const double d = clip.duration;
    for (double t : {0.0, 0.37, d / 3, d / 2 + 0.0042, 0.9 * d + 0.001, d})
      for (const oa::Animation* a : {r.ozz.animation.get(), r.ozz.animation_iframes.get()})
        r.max_relative_error = std::max(r.max_relative_error, CheckAgreement(cmu.clip, r.ozz, *a, t));
    return r;
  }();
  return result;
}

void BM_VsOzz_SampleFk_Ozz(benchmark::State& state, bool sequential, bool iframes) {
  const Cmu& cmu = LoadCmu();
  if (!cmu.clip) return state.SkipWithError(cmu.absent.c_str());
  const OzzCmuResult& r = LoadOzzCmu();
  OzzPose pose(*r.ozz.skeleton, iframes ? *r.ozz.animation_iframes : *r.ozz.animation);
  const double duration = cmu.clip->duration;
  double t = 0;
  size_t i = 0;
  for (auto _ : state) {
    if (!sequential) t = cmu.seek_times[i++ % kSeekTimes];
    if (!pose.Sample(static_cast<float>(t / duration)) || !pose.Fk()) return state.SkipWithError("ozz sampling failed");
    benchmark::DoNotOptimize(pose.models.data());
    benchmark::ClobberMemory();
    if (sequential && (t += kStep) > duration) t -= duration;
  }
  SetJoints(state, pose.models.size());
  state.counters["max_rel_error"] = r.max_relative_error;
}

void BM_VsOzz_Fk_Ozz(benchmark::State& state) {
  const Cmu& cmu = LoadCmu();
  if (!cmu.clip) return state.SkipWithError(cmu.absent.c_str());
  const OzzCmuResult& r = LoadOzzCmu();
  OzzPose pose(*r.ozz.skeleton, *r.ozz.animation);
  if (!pose.Sample(1.f / 3)) return state.SkipWithError("ozz sampling failed");
  for (auto _ : state) {
    if (!pose.Fk()) return state.SkipWithError("ozz LocalToModelJob failed");
    benchmark::DoNotOptimize(pose.models.data());
    benchmark::ClobberMemory();
  }
  SetJoints(state, pose.models.size());
}

// ozz's SkinningJob on the same mesh: per call, the skinning matrices
// (model × inverse bind, which our job also computes per call) and the
// positions and normals of every vertex. Checked once against our LBS.
void BM_VsOzz_Skin_Ozz(benchmark::State& state) {
  const armature_bench::CylinderRig& rig = armature_bench::MakeCylinderRig(kSkinRings, false);
  const Mesh& mesh = rig.mesh;
  const size_t n = mesh.vertex_count();
  constexpr int kInfluences = 4;
  std::vector<uint16_t> indices(kInfluences * n, 0);
  std::vector<float> weights((kInfluences - 1) * n, 0.f);  // ozz derives the last weight
  std::vector<float> in_positions(3 * n), in_normals(3 * n), positions(3 * n), normals(3 * n);
  for (size_t v = 0; v < n; ++v) {
    const uint32_t first = mesh.influence_offsets[v], count = mesh.influence_offsets[v + 1] - first;
    if (count > kInfluences) Fail("the cylinder has a vertex with more than 4 influences");
    for (uint32_t k = 0; k < count; ++k) {
      indices[kInfluences * v + k] = static_cast<uint16_t>(mesh.influence_joints[first + k]);
      if (k + 1 < kInfluences) weights[(kInfluences - 1) * v + k] = mesh.influence_weights[first + k];
    }
    for (int c = 0; c < 3; ++c) {
      in_positions[3 * v + static_cast<size_t>(c)] = mesh.positions[v][c];
      in_normals[3 * v + static_cast<size_t>(c)] = mesh.normals[v][c];
    }
  }
  ozz::vector<om::Float4x4> models, inverse_bind, skinning(mesh.joints.size());
  for (const Eigen::Affine3d& w : rig.world) models.push_back(ToOzz(w));
  for (const Eigen::Affine3d& ib : mesh.inverse_bind) inverse_bind.push_back(ToOzz(ib));

  ozz::geometry::SkinningJob job;
  job.vertex_count = static_cast<int>(n);
  job.influences_count = kInfluences;
  job.joint_matrices = ozz::make_span(skinning);
  job.joint_indices = ozz::make_span(indices);
  job.joint_indices_stride = kInfluences * sizeof(uint16_t);
  job.joint_weights = ozz::make_span(weights);
  job.joint_weights_stride = (kInfluences - 1) * sizeof(float);
  job.in_positions = ozz::make_span(in_positions);
  job.in_positions_stride = 3 * sizeof(float);
  job.in_normals = ozz::make_span(in_normals);
  job.in_normals_stride = 3 * sizeof(float);
  job.out_positions = ozz::make_span(positions);
  job.out_positions_stride = 3 * sizeof(float);
  job.out_normals = ozz::make_span(normals);
  job.out_normals_stride = 3 * sizeof(float);
  auto run = [&] {
    for (size_t k = 0; k < skinning.size(); ++k)
      skinning[k] = models[static_cast<size_t>(mesh.joints[k])] * inverse_bind[k];
    return job.Run();
  };

  static const bool checked = [&] {  // against our LBS, once
    std::vector<float> ours(3 * n), our_normals(3 * n);
    SkinningWorkspace ws;
    SkinningJob lbs;
    lbs.mesh = &mesh;
    lbs.joint_world = rig.world;
    lbs.parallel = false;
    lbs.positions = ours;
    lbs.normals = our_normals;
    lbs.workspace = &ws;
    if (!lbs.Run().ok() || !run()) Fail("skinning failed in the ozz check");
    // ozz leaves a blended normal unnormalized, ours is unit length: compare directions.
    for (size_t v = 0; v < n; ++v) {
      const Eigen::Map<const Eigen::Vector3f> p(&ours[3 * v]), q(&positions[3 * v]);
      const Eigen::Map<const Eigen::Vector3f> a(&our_normals[3 * v]), b(&normals[3 * v]);
      if ((p - q).norm() > 1e-4f || (a - b.normalized()).norm() > 1e-4f)
        Fail("ozz and Armature skin vertex " + std::to_string(v) + " differently");
    }
    return true;
  }();
  benchmark::DoNotOptimize(checked);
  for (auto _ : state) {
    if (!run()) return state.SkipWithError("ozz skinning failed");
    benchmark::DoNotOptimize(positions.data());
    benchmark::ClobberMemory();
  }
  SetVertices(state, n);
}

#else  // no ozz in this build: its halves skip, saying why

void BM_VsOzz_SampleFk_Ozz(benchmark::State& state, bool, bool) {
  state.SkipWithError("ozz-animation not built: " ARMATURE_NO_OZZ_REASON);
}
void BM_VsOzz_Fk_Ozz(benchmark::State& state) {
  state.SkipWithError("ozz-animation not built: " ARMATURE_NO_OZZ_REASON);
}
void BM_VsOzz_Skin_Ozz(benchmark::State& state) {
  state.SkipWithError("ozz-animation not built: " ARMATURE_NO_OZZ_REASON);
}

#endif

BENCHMARK_CAPTURE(BM_VsOzz_SampleFk_Armature, Sequential, true)->Name("BM_VsOzz_SampleFk_Sequential_Armature");
BENCHMARK_CAPTURE(BM_VsOzz_SampleFk_Ozz, Sequential, true, false)->Name("BM_VsOzz_SampleFk_Sequential_Ozz");
BENCHMARK_CAPTURE(BM_VsOzz_SampleFk_Armature, RandomSeek, false)->Name("BM_VsOzz_SampleFk_RandomSeek_Armature");
BENCHMARK_CAPTURE(BM_VsOzz_SampleFk_Ozz, RandomSeek, false, false)->Name("BM_VsOzz_SampleFk_RandomSeek_Ozz");
BENCHMARK_CAPTURE(BM_VsOzz_SampleFk_Ozz, RandomSeekIframes, false, true)
    ->Name("BM_VsOzz_SampleFk_RandomSeek_OzzIframes");
BENCHMARK_CAPTURE(BM_VsOzz_Fk_Armature, Fk, false, false)->Name("BM_VsOzz_Fk_Armature");
BENCHMARK(BM_VsOzz_Fk_Ozz);
BENCHMARK_CAPTURE(BM_VsOzz_Fk_Armature, FkScalar, true, false)->Name("BM_VsOzz_Fk_ArmatureScalar");
BENCHMARK_CAPTURE(BM_VsOzz_Fk_Armature, FkRotations, false, true)->Name("BM_VsOzz_FkRotations_Armature");
BENCHMARK_CAPTURE(BM_VsOzz_Fk_Armature, FkRotationsScalar, true, true)->Name("BM_VsOzz_FkRotations_ArmatureScalar");
BENCHMARK(BM_VsOzz_Skin_Armature);
BENCHMARK(BM_VsOzz_Skin_Ozz);

}  // namespace
}  // namespace armature
