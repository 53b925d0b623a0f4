#include "armature/engine/anim/compiled_clip.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "armature/engine/math/rotation.h"
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
  return track.empty() ||
         (track.times == times && track.in_tangents.empty() && track.interpolation != Interpolation::kCubic);
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

// Where a time falls among the uniform group's keys, and for CUBIC the
// weights of keys kp = k0 − 1, k0, k1, kn = k1 + 1 (clamped) in SampleClip's
// Hermite curve with time-aware Catmull-Rom tangents: tangents are linear in
// the keys, so the whole curve is one weighted sum with per-time weights.
struct Segment {
  size_t k0 = 0, k1 = 0, kp = 0, kn = 0;
  float u = 0;
  float w[4] = {0, 1, 0, 0};
};

Segment Locate(const CompiledClip& c, double t) {
  const std::vector<double>& times = c.times;
  const size_t frames = times.size();
  Segment s;
  if (t >= times[frames - 1]) {
    s.k0 = s.k1 = s.kp = s.kn = frames - 1;
    return s;
  }
  if (!(t > times[0])) return s;
  // Key k0 with times[k0] <= t < times[k0 + 1], as SampleClip's search finds it.
  const double guess = std::floor((t - c.start) / c.frame_time);
  size_t k0 = std::min(static_cast<size_t>(std::max(guess, 0.0)), frames - 2);
  while (k0 + 2 < frames && times[k0 + 1] <= t) ++k0;
  while (k0 > 0 && times[k0] > t) --k0;
  const size_t k1 = k0 + 1;
  const double h = times[k1] - times[k0], u = (t - times[k0]) / h;
  s.k0 = k0;
  s.k1 = k1;
  s.kp = k0 > 0 ? k0 - 1 : k0;
  s.kn = k1 + 1 < frames ? k1 + 1 : k1;
  s.u = static_cast<float>(u);
  // Tangent at key i: a·(v[i+1] − v[i]) + b·(v[i] − v[i−1]) (KeyTangent, anim/cubic_tangents.h).
  auto coefficients = [&](size_t i, double& a, double& b) {
    if (i == 0) {
      a = 1 / (times[1] - times[0]), b = 0;
    } else if (i == frames - 1) {
      a = 0, b = 1 / (times[i] - times[i - 1]);
    } else {
      const double hp = times[i] - times[i - 1], hn = times[i + 1] - times[i];
      a = hp / (hn * (hp + hn)), b = hn / (hp * (hp + hn));
    }
  };
  double a0, b0, a1, b1;
  coefficients(k0, a0, b0);
  coefficients(k1, a1, b1);
  const double u2 = u * u, u3 = u2 * u;
  const double h00 = 2 * u3 - 3 * u2 + 1, h10 = (u3 - 2 * u2 + u) * h, h01 = -2 * u3 + 3 * u2, h11 = (u3 - u2) * h;
  s.w[0] = static_cast<float>(-h10 * b0);
  s.w[1] = static_cast<float>(h00 + h10 * (b0 - a0) - h11 * b1);
  s.w[2] = static_cast<float>(h01 + h10 * a0 + h11 * (b1 - a1));
  s.w[3] = static_cast<float>(h11 * a1);
  return s;
}

enum class LaneMode { kOwn, kStep, kLinear, kCubic };

// Interpolates the lanes over `seg` and writes each track's joint through
// `store(joint, values)`. kOwn: each track's own STEP or LINEAR; kCubic:
// squad through the precomputed control points `controls` (rotations) or the
// Hermite weights (vectors).
template <class Store>
void SampleLanes(const CompiledLanes& lanes, const Segment& seg, LaneMode mode, const float* controls,
                 const Store& store) {
  const size_t comps = lanes.components, frame_stride = lanes.groups * comps * 4;
  auto row = [&](const float* base, size_t k) { return base + k * frame_stride; };
  const float* keys = lanes.keys.data();
  const size_t tracks = lanes.joints.size();
  for (size_t g = 0; g < lanes.groups; ++g) {
    const size_t at = g * comps * 4;
    v4 a[4], b[4], r[4];
    for (size_t c = 0; c < comps; ++c) {
      a[c] = Load4(row(keys, seg.k0) + at + c * 4);
      b[c] = Load4(row(keys, seg.k1) + at + c * 4);
    }
    if (mode == LaneMode::kCubic && comps == 4) {
      // Squad (math/rotation.h) with keys and control points aligned to a0.
      v4 c0[4], c1[4], p[4], q[4];
      const v4 d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
      const v4 sign = compiled_internal::Select(d < Splat(0.f), Splat(-1.f), Splat(1.f));
      for (size_t c = 0; c < 4; ++c) {
        b[c] *= sign;
        c0[c] = Load4(row(controls, seg.k0) + at + c * 4);
        c1[c] = Load4(row(controls, seg.k1) + at + c * 4) * sign;
      }
      const v4 u = Splat(seg.u);
      Slerp4<false>(a, b, u, p);
      Slerp4<false>(c0, c1, u, q);
      Slerp4<false>(p, q, Splat(2.f) * u * (Splat(1.f) - u), r);
    } else if (mode == LaneMode::kCubic) {
      for (size_t c = 0; c < comps; ++c)
        r[c] = Splat(seg.w[0]) * Load4(row(keys, seg.kp) + at + c * 4) + Splat(seg.w[1]) * a[c] +
               Splat(seg.w[2]) * b[c] + Splat(seg.w[3]) * Load4(row(keys, seg.kn) + at + c * 4);
    } else {
      const v4 lu = mode == LaneMode::kStep     ? Splat(0.f)
                    : mode == LaneMode::kLinear ? Splat(seg.u)
                                                : Splat(seg.u) * Load4(lanes.linear.data() + g * 4);
      if (comps == 4) {
        Slerp4<true>(a, b, lu, r);
      } else {
        for (size_t c = 0; c < comps; ++c) r[c] = a[c] + lu * (b[c] - a[c]);
      }
    }
    const size_t end = std::min<size_t>(4, tracks - g * 4);
    for (size_t lane = 0; lane < end; ++lane) {
      float v[4] = {};
      for (size_t c = 0; c < comps; ++c) v[c] = r[c][lane];
      store(lanes.joints[g * 4 + lane], v);
    }
  }
}

// Squad's control point at each key of each rotation lane, laid out as the
// keys: SampleClip's s_out for a segment's first key and s_in for its last,
// which agree at interior keys when the neighbouring segments are equally
// long. Empty when they do not agree (uneven times): CUBIC then samples the
// source.
std::vector<float> BuildRotationControls(const Clip& clip, const CompiledLanes& lanes,
                                         const std::vector<double>& times) {
  const size_t n = times.size(), frame_stride = lanes.groups * 16;
  std::vector<float> controls(lanes.keys.size());
  for (size_t g = 0; g < lanes.groups; ++g)
    for (size_t lane = 0; lane < 4; ++lane) {
      const size_t i = g * 4 + lane;
      float* base = controls.data() + g * 16 + lane;
      if (i >= lanes.joints.size()) {
        for (size_t k = 0; k < n; ++k) base[k * frame_stride + 12] = 1;  // identity (x y z w)
        continue;
      }
      const std::vector<Eigen::Quaterniond>& q = clip.joints[lanes.joints[i]].rotation.values;
      for (size_t k = 0; k < n; ++k) {
        Eigen::Quaterniond s_out = Eigen::Quaterniond::Identity(), s_in = s_out;
        const Eigen::Quaterniond key = q[k].normalized();
        if (k + 1 < n) {  // as SampleRotation for the segment k → k + 1
          const Eigen::Quaterniond a1 = SameHemisphere(q[k + 1].normalized(), key);
          const Eigen::Quaterniond prev = k > 0 ? SameHemisphere(q[k - 1], key) : key;
          SquadControlPoints(prev, key, a1, k > 0 ? times[k] - times[k - 1] : 0.0, times[k + 1] - times[k], nullptr,
                             &s_out);
        }
        if (k > 0) {  // as SampleRotation for the segment k − 1 → k, then back to key's sign
          const Eigen::Quaterniond a0 = q[k - 1].normalized(), a1 = SameHemisphere(key, a0);
          const Eigen::Quaterniond next = k + 1 < n ? SameHemisphere(q[k + 1], a1) : a1;
          SquadControlPoints(a0, a1, next, times[k] - times[k - 1], k + 1 < n ? times[k + 1] - times[k] : 0.0, &s_in,
                             nullptr);
          if (a1.coeffs().dot(key.coeffs()) < 0) s_in.coeffs() = -s_in.coeffs();
        }
        if (k > 0 && k + 1 < n && s_in.angularDistance(s_out) > 1e-7) return {};
        const Eigen::Quaterniond& c = k + 1 < n ? s_out : s_in;
        for (int comp = 0; comp < 4; ++comp) base[k * frame_stride + comp * 4] = static_cast<float>(c.coeffs()[comp]);
      }
    }
  return controls;
}

size_t LaneBytes(const CompiledLanes& l) {
  return l.keys.size() * sizeof(float) + l.linear.size() * sizeof(float) + l.joints.size() * sizeof(uint32_t);
}

}  // namespace

size_t CompiledClip::KeyBytes() const {
  return times.size() * sizeof(double) + LaneBytes(rotations) +
         (controls_ready_.load(std::memory_order_acquire) ? rotation_controls_.size() * sizeof(float) : 0) +
         LaneBytes(translations) + LaneBytes(scales) + fallback_joints.size() * sizeof(uint32_t);
}

const std::vector<float>& CompiledClip::RotationControls() const {
  std::call_once(controls_once_, [this] {
    rotation_controls_ = BuildRotationControls(*source, rotations, times);
    controls_ready_.store(true, std::memory_order_release);
  });
  return rotation_controls_;
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
  const bool cubic = options.interpolation == Interpolation::kCubic;
  const std::vector<float>* controls = cubic ? &compiled.RotationControls() : nullptr;
  if (cubic && controls->size() != compiled.rotations.keys.size()) return SampleClip(clip, time, options, out);
  const Skeleton& sk = *clip.skeleton;
  std::copy(sk.rest.begin(), sk.rest.end(), out.begin());
  const double t = WrapTime(time, clip.duration, options.wrap);
  if (compiled.times.size() >= 2) {
    const Segment seg = Locate(compiled, t);
    const LaneMode mode = !options.interpolation                             ? LaneMode::kOwn
                          : *options.interpolation == Interpolation::kStep   ? LaneMode::kStep
                          : *options.interpolation == Interpolation::kLinear ? LaneMode::kLinear
                                                                             : LaneMode::kCubic;
    SampleLanes(compiled.rotations, seg, mode, controls ? controls->data() : nullptr,
                [&](uint32_t j, const float* v) { out[j].rotation = Eigen::Quaterniond(v[3], v[0], v[1], v[2]); });
    SampleLanes(compiled.translations, seg, mode, nullptr,
                [&](uint32_t j, const float* v) { out[j].translation = Eigen::Vector3d(v[0], v[1], v[2]); });
    SampleLanes(compiled.scales, seg, mode, nullptr,
                [&](uint32_t j, const float* v) { out[j].scale = Eigen::Vector3d(v[0], v[1], v[2]); });
  }
  for (uint32_t j : compiled.fallback_joints) SampleJoint(clip.joints[j], t, options.interpolation, out[j]);
  return Status::Ok();
}

}  // namespace armature
