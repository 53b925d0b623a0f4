#include "armature/engine/anim/compiled_clip.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "fast_slerp.h"
#include "sample_checks.h"

namespace armature {
namespace {

using compiled_internal::Load4;
using compiled_internal::Slerp4;
using compiled_internal::Splat;
using compiled_internal::v4;

// The uniform group's times: those of the first track with two keys or
// more, when they are close enough to evenly spaced for floor() to land
// within one key of the right one.
std::vector<double> UniformTimes(const Clip& clip) {
  for (const JointTrack& jt : clip.joints)
    for (const std::vector<double>* times : {&jt.rotation.times, &jt.translation.times, &jt.scale.times}) {
      const size_t n = times->size();
      if (n < 2) continue;
      const double start = (*times)[0], step = ((*times)[n - 1] - start) / static_cast<double>(n - 1);
      for (size_t k = 0; k < n; ++k)
        if (std::abs((*times)[k] - (start + static_cast<double>(k) * step)) > 0.25 * step) return {};
      return *times;
    }
  return {};
}

template <class V>
bool InGroup(const Track<V>& track, const std::vector<double>& times) {
  return track.empty() || (track.times == times && track.in_tangents.empty() &&
                           track.interpolation != Interpolation::kCubic);
}

// Lanes of the joints in `joints` for one property; `value(jt, k)` writes key
// k's components; `identity` fills the padding lanes.
template <class Has, class Value>
CompiledLanes BuildLanes(const Clip& clip, const std::vector<uint32_t>& joints, size_t components, size_t frames,
                         const float* identity, const Has& has, const Value& value) {
  CompiledLanes lanes;
  lanes.components = components;
  for (uint32_t j : joints)
    if (has(clip.joints[j])) lanes.joints.push_back(j);
  lanes.groups = (lanes.joints.size() + 3) / 4;
  lanes.linear.assign(lanes.groups * 4, 0.f);
  lanes.keys.resize(frames * lanes.groups * components * 4);
  const size_t frame_stride = lanes.groups * components * 4;
  for (size_t g = 0; g < lanes.groups; ++g)
    for (size_t lane = 0; lane < 4; ++lane) {
      const size_t i = g * 4 + lane;
      float* base = lanes.keys.data() + g * components * 4 + lane;
      float v[4];
      for (size_t k = 0; k < frames; ++k) {
        if (i < lanes.joints.size())
          value(clip.joints[lanes.joints[i]], k, v);
        else
          std::copy(identity, identity + components, v);
        for (size_t c = 0; c < components; ++c) base[k * frame_stride + c * 4] = v[c];
      }
      if (i < lanes.joints.size()) lanes.linear[i] = 1.f;
    }
  return lanes;
}

// Marks STEP tracks (their own interpolation) in `lanes.linear`.
template <class Get>
void MarkStep(const Clip& clip, CompiledLanes& lanes, const Get& track) {
  for (size_t i = 0; i < lanes.joints.size(); ++i)
    if (track(clip.joints[lanes.joints[i]]).interpolation == Interpolation::kStep) lanes.linear[i] = 0.f;
}

// Interpolates lanes between frames k0 and k1 at u (0 for STEP lanes unless
// `all_linear`; 0 for all when `step`) and
// writes each track's joint through `store(joint, values)`.
template <class Store>
void SampleLanes(const CompiledLanes& lanes, size_t k0, size_t k1, float u, bool step, bool all_linear,
                 const Store& store) {
  const size_t comps = lanes.components, frame_stride = lanes.groups * comps * 4;
  const float* row0 = lanes.keys.data() + k0 * frame_stride;
  const float* row1 = lanes.keys.data() + k1 * frame_stride;
  const size_t tracks = lanes.joints.size();
  for (size_t g = 0; g < lanes.groups; ++g) {
    const v4 lu = step ? Splat(0.f) : all_linear ? Splat(u) : Splat(u) * Load4(lanes.linear.data() + g * 4);
    v4 a[4], b[4], r[4];
    for (size_t c = 0; c < comps; ++c) {
      a[c] = Load4(row0 + (g * comps + c) * 4);
      b[c] = Load4(row1 + (g * comps + c) * 4);
    }
    if (comps == 4) {
      Slerp4(a, b, lu, r);
    } else {
      for (size_t c = 0; c < comps; ++c) r[c] = a[c] + lu * (b[c] - a[c]);
    }
    const size_t end = std::min<size_t>(4, tracks - g * 4);
    for (size_t lane = 0; lane < end; ++lane) {
      float v[4] = {};
      for (size_t c = 0; c < comps; ++c) v[c] = r[c][lane];
      store(lanes.joints[g * 4 + lane], v);
    }
  }
}

size_t LaneBytes(const CompiledLanes& l) {
  return l.keys.size() * sizeof(float) + l.linear.size() * sizeof(float) + l.joints.size() * sizeof(uint32_t);
}

}  // namespace

size_t CompiledClip::KeyBytes() const {
  return times.size() * sizeof(double) + LaneBytes(rotations) + LaneBytes(translations) + LaneBytes(scales) +
         fallback_joints.size() * sizeof(uint32_t);
}

StatusOr<std::shared_ptr<const CompiledClip>> CompileClip(std::shared_ptr<const Clip> clip) {
  if (!clip) return Status::InvalidArgument("no clip to compile");
  ARMATURE_RETURN_IF_ERROR(clip->Validate());
  auto out = std::make_shared<CompiledClip>();
  out->source = clip;
  out->times = UniformTimes(*clip);
  const size_t frames = out->times.size();
  if (frames >= 2) {
    out->start = out->times.front();
    out->frame_time = (out->times.back() - out->start) / static_cast<double>(frames - 1);
  }
  std::vector<uint32_t> grouped;
  for (uint32_t j = 0; j < clip->joints.size(); ++j) {
    const JointTrack& jt = clip->joints[j];
    if (jt.rotation.empty() && jt.translation.empty() && jt.scale.empty()) continue;
    if (frames >= 2 && InGroup(jt.rotation, out->times) && InGroup(jt.translation, out->times) &&
        InGroup(jt.scale, out->times))
      grouped.push_back(j);
    else
      out->fallback_joints.push_back(j);
  }
  static constexpr float kIdentityQ[4] = {0, 0, 0, 1}, kZero[3] = {0, 0, 0}, kOne[3] = {1, 1, 1};
  out->rotations = BuildLanes(
      *clip, grouped, 4, frames, kIdentityQ, [](const JointTrack& jt) { return !jt.rotation.empty(); },
      [](const JointTrack& jt, size_t k, float* v) {
        const Eigen::Quaterniond q = jt.rotation.values[k].normalized();
        for (int c = 0; c < 4; ++c) v[c] = static_cast<float>(q.coeffs()[c]);  // x y z w
      });
  out->translations = BuildLanes(
      *clip, grouped, 3, frames, kZero, [](const JointTrack& jt) { return !jt.translation.empty(); },
      [](const JointTrack& jt, size_t k, float* v) {
        for (int c = 0; c < 3; ++c) v[c] = static_cast<float>(jt.translation.values[k][c]);
      });
  out->scales = BuildLanes(
      *clip, grouped, 3, frames, kOne, [](const JointTrack& jt) { return !jt.scale.empty(); },
      [](const JointTrack& jt, size_t k, float* v) {
        for (int c = 0; c < 3; ++c) v[c] = static_cast<float>(jt.scale.values[k][c]);
      });
  MarkStep(*clip, out->rotations, [](const JointTrack& jt) -> const QuatTrack& { return jt.rotation; });
  MarkStep(*clip, out->translations, [](const JointTrack& jt) -> const Vec3Track& { return jt.translation; });
  MarkStep(*clip, out->scales, [](const JointTrack& jt) -> const Vec3Track& { return jt.scale; });
  return std::shared_ptr<const CompiledClip>(std::move(out));
}

Status SampleCompiledClip(const CompiledClip& compiled, double time, const SampleOptions& options, std::span<Trs> out) {
  if (!compiled.source) return Status::InvalidArgument("compiled clip has no source clip");
  const Clip& clip = *compiled.source;
  ARMATURE_RETURN_IF_ERROR(anim_internal::CheckSampleArguments(clip, time, options, out.size()));
  if (options.interpolation == Interpolation::kCubic) return SampleClip(clip, time, options, out);
  const Skeleton& sk = *clip.skeleton;
  std::copy(sk.rest.begin(), sk.rest.end(), out.begin());
  const double t = WrapTime(time, clip.duration, options.wrap);
  const size_t frames = compiled.times.size();
  if (frames >= 2) {
    // Key k0 with times[k0] <= t < times[k0 + 1], as SampleClip's search finds it.
    size_t k0 = 0, k1 = 0;
    double u = 0;
    if (t >= compiled.times[frames - 1]) {
      k0 = k1 = frames - 1;
    } else if (t > compiled.times[0]) {
      const double guess = std::floor((t - compiled.start) / compiled.frame_time);
      k0 = std::min(static_cast<size_t>(std::max(guess, 0.0)), frames - 2);
      while (k0 + 2 < frames && compiled.times[k0 + 1] <= t) ++k0;
      while (k0 > 0 && compiled.times[k0] > t) --k0;
      k1 = k0 + 1;
      u = (t - compiled.times[k0]) / (compiled.times[k1] - compiled.times[k0]);
    }
    const bool step = options.interpolation == Interpolation::kStep;
    const bool all_linear = options.interpolation == Interpolation::kLinear;
    const float fu = static_cast<float>(u);
    auto lanes = [&](const CompiledLanes& l, auto store) { SampleLanes(l, k0, k1, fu, step, all_linear, store); };
    lanes(compiled.rotations, [&](uint32_t j, const float* v) {
      out[j].rotation = Eigen::Quaterniond(v[3], v[0], v[1], v[2]);
    });
    lanes(compiled.translations,
          [&](uint32_t j, const float* v) { out[j].translation = Eigen::Vector3d(v[0], v[1], v[2]); });
    lanes(compiled.scales, [&](uint32_t j, const float* v) { out[j].scale = Eigen::Vector3d(v[0], v[1], v[2]); });
  }
  for (uint32_t j : compiled.fallback_joints) SampleJoint(clip.joints[j], t, options.interpolation, out[j]);
  return Status::Ok();
}

}  // namespace armature
