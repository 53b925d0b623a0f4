#include "armature/engine/anim/clip.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "armature/engine/anim/cubic_tangents.h"
#include "armature/engine/math/rotation.h"
#include "sample_checks.h"

namespace armature {
namespace {

// Where a time falls among a track's keys: between keys k0 and k1 = k0 + 1 at
// fraction u of the segment of length h, or on a single key (k0 == k1).
struct KeySpan {
  size_t k0 = 0, k1 = 0;
  double u = 0, h = 0;
};

KeySpan Locate(std::span<const double> times, double t) {
  const size_t n = times.size();
  if (n == 1 || t <= times[0]) return {};
  if (t >= times[n - 1]) return {n - 1, n - 1, 0, 0};
  const size_t k1 = static_cast<size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin());
  const size_t k0 = k1 - 1;
  const double h = times[k1] - times[k0];
  return {k0, k1, (t - times[k0]) / h, h};
}

// Cubic Hermite on the unit segment; m0, m1 are slopes per unit of u.
template <class V>
V Hermite(const V& p0, const V& m0, const V& p1, const V& m1, double u) {
  const double u2 = u * u, u3 = u2 * u;
  return (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * p1 + (u3 - u2) * m1;
}

// Samples a vector-valued key sequence. `value(k)` reads key k; `in(k)` and
// `out(k)` its glTF tangents when `has_tangents`.
template <class V, class ValueAt, class InAt, class OutAt>
V SampleKeys(std::span<const double> times, const ValueAt& value, bool has_tangents, const InAt& in, const OutAt& out,
             double t, Interpolation mode) {
  const KeySpan s = Locate(times, t);
  if (s.u == 0 || mode == Interpolation::kStep) return value(s.k0);  // on a key (k0 == k1 has u 0)
  if (mode == Interpolation::kLinear) return V(value(s.k0) + s.u * (value(s.k1) - value(s.k0)));
  if (has_tangents) return Hermite<V>(value(s.k0), out(s.k0) * s.h, value(s.k1), in(s.k1) * s.h, s.u);
  return Hermite<V>(value(s.k0), KeyTangent<V>(times, value, s.k0) * s.h, value(s.k1),
                    KeyTangent<V>(times, value, s.k1) * s.h, s.u);
}

Eigen::Vector3d SampleVec3(const Vec3Track& track, double t, Interpolation mode) {
  const auto& v = track.values;
  const auto& in = track.in_tangents;
  const auto& out = track.out_tangents;
  return SampleKeys<Eigen::Vector3d>(
      track.times, [&](size_t k) -> const Eigen::Vector3d& { return v[k]; }, !in.empty() && !out.empty(),
      [&](size_t k) -> const Eigen::Vector3d& { return in[k]; },
      [&](size_t k) -> const Eigen::Vector3d& { return out[k]; }, t, mode);
}

Eigen::Quaterniond SampleRotation(const QuatTrack& track, double t, Interpolation mode) {
  const auto& times = track.times;
  const auto& q = track.values;
  const KeySpan s = Locate(times, t);
  // On a key (k0 == k1 has u 0), every mode gives the key: no slerp. A clip
  // sampled at its own frames, as compression's reference does, is all keys.
  if (s.u == 0 || mode == Interpolation::kStep) return q[s.k0].normalized();
  if (mode == Interpolation::kLinear) return Slerp(q[s.k0], q[s.k1], s.u).normalized();
  if (!track.in_tangents.empty() && !track.out_tangents.empty()) {
    // glTF CUBICSPLINE: Hermite on the components, then normalize (glTF 2.0 spec, Appendix C).
    const Eigen::Vector4d r = Hermite<Eigen::Vector4d>(q[s.k0].coeffs(), track.out_tangents[s.k0].coeffs() * s.h,
                                                       q[s.k1].coeffs(), track.in_tangents[s.k1].coeffs() * s.h, s.u);
    return Eigen::Quaterniond(r.normalized());
  }
  // Squad through keys aligned to one hemisphere, with time-aware control points.
  const size_t n = times.size();
  const Eigen::Quaterniond a0 = q[s.k0].normalized();
  const Eigen::Quaterniond a1 = SameHemisphere(q[s.k1].normalized(), a0);
  const Eigen::Quaterniond prev = s.k0 > 0 ? SameHemisphere(q[s.k0 - 1], a0) : a0;
  const Eigen::Quaterniond next = s.k1 + 1 < n ? SameHemisphere(q[s.k1 + 1], a1) : a1;
  const double dt_prev = s.k0 > 0 ? times[s.k0] - times[s.k0 - 1] : 0.0;
  const double dt_next = s.k1 + 1 < n ? times[s.k1 + 1] - times[s.k1] : 0.0;
  Eigen::Quaterniond s_out, s_in;
  SquadControlPoints(prev, a0, a1, dt_prev, s.h, nullptr, &s_out);
  SquadControlPoints(a0, a1, next, s.h, dt_next, &s_in, nullptr);
  return Squad(a0, s_out, s_in, a1, s.u).normalized();
}

std::string KeyError(const std::string& where, size_t k, const std::string& what) {
  return where + ": key " + std::to_string(k) + " " + what;
}

Status ValidateTimes(const std::vector<double>& times, const std::string& where) {
  for (size_t k = 0; k < times.size(); ++k) {
    if (!std::isfinite(times[k])) return Status::InvalidArgument(KeyError(where, k, "time is not finite"));
    if (k > 0 && !(times[k] > times[k - 1]))
      return Status::InvalidArgument(KeyError(where, k,
                                              "time " + std::to_string(times[k]) +
                                                  " does not increase (previous key at " +
                                                  std::to_string(times[k - 1]) + ")"));
  }
  return Status::Ok();
}

// Enums can arrive as integers from outside (files, requests): an unknown
// value is an error, never a silent default.
Status CheckInterpolation(Interpolation i, const std::string& where) {
  if (i == Interpolation::kStep || i == Interpolation::kLinear || i == Interpolation::kCubic) return Status::Ok();
  return Status::InvalidArgument(where + ": interpolation " + std::to_string(static_cast<int>(i)) +
                                 " is not STEP, LINEAR or CUBIC");
}

bool Finite(const Eigen::Vector3d& v) { return v.allFinite(); }
bool Finite(const Eigen::Quaterniond& q) { return q.coeffs().allFinite(); }

template <class V, class Check>
Status ValidateTrack(const Track<V>& track, const std::string& where, const Check& check_value) {
  ARMATURE_RETURN_IF_ERROR(ValidateTimes(track.times, where));
  ARMATURE_RETURN_IF_ERROR(CheckInterpolation(track.interpolation, where));
  const size_t n = track.times.size();
  if (track.values.size() != n)
    return Status::InvalidArgument(where + ": " + std::to_string(track.values.size()) + " values for " +
                                   std::to_string(n) + " key times");
  if (track.in_tangents.size() != track.out_tangents.size() ||
      (!track.in_tangents.empty() && track.in_tangents.size() != n))
    return Status::InvalidArgument(where + ": in/out tangents must both be empty or have one per key (" +
                                   std::to_string(n) + ")");
  for (size_t k = 0; k < n; ++k) {
    if (std::string e = check_value(track.values[k]); !e.empty()) return Status::InvalidArgument(KeyError(where, k, e));
    if (!track.in_tangents.empty() && (!Finite(track.in_tangents[k]) || !Finite(track.out_tangents[k])))
      return Status::InvalidArgument(KeyError(where, k, "tangent is not finite"));
  }
  return Status::Ok();
}

std::string CheckVec3(const Eigen::Vector3d& v) { return Finite(v) ? "" : "value is not finite"; }

std::string CheckUnitQuaternion(const Eigen::Quaterniond& q) {
  if (!q.coeffs().allFinite()) return "rotation is not finite";
  if (std::abs(q.norm() - 1.0) > 1e-3)
    return "rotation is not a unit quaternion (norm " + std::to_string(q.norm()) + ")";
  return "";
}

}  // namespace

Status Clip::Validate() const {
  if (!skeleton) return Status::InvalidArgument("clip has no skeleton");
  const Skeleton& sk = *skeleton;
  if (joints.size() != sk.size())
    return Status::InvalidArgument("clip has " + std::to_string(joints.size()) + " joint tracks, the skeleton has " +
                                   std::to_string(sk.size()) + " joints");
  if (!std::isfinite(duration) || duration < 0)
    return Status::InvalidArgument("clip duration " + std::to_string(duration) + " is not a finite value >= 0");
  if (!std::isfinite(frame_time) || frame_time < 0)
    return Status::InvalidArgument("clip frame_time " + std::to_string(frame_time) + " is not a finite value >= 0");
  for (size_t i = 0; i < joints.size(); ++i) {
    const std::string joint = "joint '" + sk.names[i] + "' ";
    ARMATURE_RETURN_IF_ERROR(ValidateTrack(joints[i].translation, joint + "translation track", CheckVec3));
    ARMATURE_RETURN_IF_ERROR(ValidateTrack(joints[i].rotation, joint + "rotation track", CheckUnitQuaternion));
    ARMATURE_RETURN_IF_ERROR(ValidateTrack(joints[i].scale, joint + "scale track", CheckVec3));
  }
  for (const WeightsTrack& w : weights) {
    const std::string where = "weights track of mesh '" + w.mesh + "'";
    ARMATURE_RETURN_IF_ERROR(ValidateTimes(w.times, where));
    ARMATURE_RETURN_IF_ERROR(CheckInterpolation(w.interpolation, where));
    const size_t plain = w.times.size() * w.targets;
    const bool ok_size =
        w.values.size() == plain || (w.interpolation == Interpolation::kCubic && w.values.size() == 3 * plain);
    if (!ok_size)
      return Status::InvalidArgument(where + ": " + std::to_string(w.values.size()) +
                                     " values, expected keys × targets = " + std::to_string(plain) +
                                     (w.interpolation == Interpolation::kCubic ? " (or 3× that)" : ""));
    for (size_t k = 0; k < w.values.size(); ++k)
      if (!std::isfinite(w.values[k]))
        return Status::InvalidArgument(where + ": value " + std::to_string(k) + " is not finite");
  }
  return Status::Ok();
}

double WrapTime(double time, double duration, WrapMode wrap) {
  if (!(duration > 0) || !std::isfinite(time)) return 0.0;
  if (wrap == WrapMode::kClamp) return std::clamp(time, 0.0, duration);
  double r = std::fmod(time, duration);
  if (r < 0) r += duration;
  return r < duration ? r : 0.0;  // r + duration can round up to duration
}

namespace anim_internal {

Status CheckSampleArguments(const Clip& clip, double time, const SampleOptions& options, size_t out_size) {
  if (!clip.skeleton) return Status::InvalidArgument("clip has no skeleton");
  const Skeleton& sk = *clip.skeleton;
  if (out_size != sk.size())
    return Status::InvalidArgument("output has room for " + std::to_string(out_size) +
                                   " transforms, the skeleton has " + std::to_string(sk.size()) + " joints");
  if (clip.joints.size() != sk.size())
    return Status::InvalidArgument("clip has " + std::to_string(clip.joints.size()) +
                                   " joint tracks, the skeleton has " + std::to_string(sk.size()) + " joints");
  if (!std::isfinite(time)) return Status::InvalidArgument("time is not finite");
  if (options.interpolation) ARMATURE_RETURN_IF_ERROR(CheckInterpolation(*options.interpolation, "sample options"));
  if (options.wrap != WrapMode::kClamp && options.wrap != WrapMode::kLoop)
    return Status::InvalidArgument("sample options: wrap mode " + std::to_string(static_cast<int>(options.wrap)) +
                                   " is not CLAMP or LOOP");
  return Status::Ok();
}

}  // namespace anim_internal

Status SampleClip(const Clip& clip, double time, const SampleOptions& options, std::span<Trs> out) {
  ARMATURE_RETURN_IF_ERROR(anim_internal::CheckSampleArguments(clip, time, options, out.size()));
  const Skeleton& sk = *clip.skeleton;
  const double t = WrapTime(time, clip.duration, options.wrap);
  for (size_t i = 0; i < sk.size(); ++i) {
    out[i] = sk.rest[i];
    SampleJoint(clip.joints[i], t, options.interpolation, out[i]);
  }
  return Status::Ok();
}

void SampleJoint(const JointTrack& jt, double t, const std::optional<Interpolation>& interpolation, Trs& o) {
  if (!jt.translation.empty())
    o.translation = SampleVec3(jt.translation, t, interpolation.value_or(jt.translation.interpolation));
  if (!jt.rotation.empty())
    o.rotation = SampleRotation(jt.rotation, t, interpolation.value_or(jt.rotation.interpolation));
  if (!jt.scale.empty()) o.scale = SampleVec3(jt.scale, t, interpolation.value_or(jt.scale.interpolation));
}

void SampleWeights(const WeightsTrack& track, double time, const SampleOptions& options, std::span<double> out) {
  const size_t n = track.times.size(), targets = track.targets;
  const size_t m = std::min(out.size(), targets);
  const bool triplets = track.interpolation == Interpolation::kCubic && track.values.size() == 3 * n * targets;
  if (n == 0 || (!triplets && track.values.size() != n * targets)) {
    std::fill(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(m), 0.0);
    return;
  }
  const double t = WrapTime(time, track.times.back(), options.wrap);
  const Interpolation mode = options.interpolation.value_or(track.interpolation);
  const double* v = track.values.data();
  // glTF CUBICSPLINE stores in-tangent, value, out-tangent per key.
  const size_t stride = triplets ? 3 * targets : targets, value_at = triplets ? targets : 0;
  for (size_t j = 0; j < m; ++j) {
    out[j] = SampleKeys<double>(
        track.times, [&](size_t k) { return v[k * stride + value_at + j]; }, triplets,
        [&](size_t k) { return v[k * stride + j]; }, [&](size_t k) { return v[k * stride + 2 * targets + j]; }, t,
        mode);
  }
}

}  // namespace armature
