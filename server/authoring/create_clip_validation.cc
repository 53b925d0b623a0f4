#include "server/authoring/create_clip_validation.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <string_view>

#include "armature/base/closest_name.h"
#include "armature/engine/math/rotation.h"
#include "server/rpc/request_validation.h"

namespace armature::server {
namespace {

constexpr double kUnitTolerance = 1e-3;
constexpr double kMaxFloat = std::numeric_limits<float>::max();

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// Errors of one entry: "tracks[2] (joint 'Head')".
class EntryErrors {
 public:
  EntryErrors(int index, const std::string& joint)
      : where_("tracks[" + std::to_string(index) + "]" + (joint.empty() ? "" : " (joint '" + joint + "')")) {}
  Status Bad(const std::string& what) const { return Status::InvalidArgument(where_ + ": " + what); }
  Status BadKey(size_t k, const std::string& what) const {
    return Status::InvalidArgument(where_ + ": key " + std::to_string(k) + ": " + what);
  }
  const std::string& where() const { return where_; }

 private:
  std::string where_;
};

Status CheckTimes(const google::protobuf::RepeatedField<double>& times, const EntryErrors& e) {
  for (int k = 0; k < times.size(); ++k) {
    const double t = times[k];
    if (!std::isfinite(t)) return e.BadKey(k, "time is not finite");
    if (t < 0) return e.BadKey(k, "time " + Num(t) + " is negative");
    if (t > kMaxFloat) return e.BadKey(k, "time " + Num(t) + " is beyond a 32-bit float");
    if (k == 0) continue;
    const double p = times[k - 1];
    if (t == p) return e.BadKey(k, "time " + Num(t) + " repeats key " + std::to_string(k - 1));
    if (t < p)
      return e.BadKey(k, "time " + Num(t) + " does not increase (key " + std::to_string(k - 1) + " is at " + Num(p) +
                             "); times must be sorted");
    if (StoredKeyTime(t) <= StoredKeyTime(p))
      return e.BadKey(k, "time " + Num(t) + " equals key " + std::to_string(k - 1) + "'s " + Num(p) +
                             " as a 32-bit float (glTF stores times as floats)");
  }
  return Status::Ok();
}

// `values` holds `per_key` numbers per key, finite and within float range.
Status CheckValues(const google::protobuf::RepeatedField<double>& values, size_t keys, int per_key,
                   const std::string& channel, const std::string& layout, const EntryErrors& e) {
  const size_t expected = keys * static_cast<size_t>(per_key);
  if (static_cast<size_t>(values.size()) != expected)
    return e.Bad(channel + ": " + std::to_string(values.size()) + " values for " + std::to_string(keys) +
                 " keys; expected " + std::to_string(per_key) + " per key (" + layout + "), " +
                 std::to_string(expected));
  for (int i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i]))
      return e.BadKey(static_cast<size_t>(i / per_key),
                      channel + " value " + std::to_string(i % per_key) + " is not finite (NaN or Inf)");
    if (std::abs(values[i]) > kMaxFloat)
      return e.BadKey(static_cast<size_t>(i / per_key),
                      channel + " value " + Num(values[i]) + " is beyond a 32-bit float");
  }
  return Status::Ok();
}

std::vector<Eigen::Vector3d> Vec3s(const google::protobuf::RepeatedField<double>& v) {
  std::vector<Eigen::Vector3d> out(static_cast<size_t>(v.size() / 3));
  for (size_t k = 0; k < out.size(); ++k) out[k] = Eigen::Vector3d(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
  return out;
}

// w, x, y, z per key (the API's order) → Eigen's.
std::vector<Eigen::Quaterniond> Quats(const google::protobuf::RepeatedField<double>& v) {
  std::vector<Eigen::Quaterniond> out(static_cast<size_t>(v.size() / 4));
  for (size_t k = 0; k < out.size(); ++k)
    out[k] = Eigen::Quaterniond(v[4 * k], v[4 * k + 1], v[4 * k + 2], v[4 * k + 3]);
  return out;
}

// A channel's optional tangents: only on CUBIC tracks with that channel.
template <class V, class Convert>
Status ReadTangents(bool has, const v1::KeyTangents& tangents, bool has_channel, size_t n, int per_key,
                    const std::string& channel, const std::string& layout, bool cubic, const EntryErrors& e,
                    const Convert& convert, Track<V>& track) {
  if (!has) return Status::Ok();
  if (!cubic) return e.Bad(channel + ": tangents are only for CUBIC tracks");
  if (!has_channel) return e.Bad(channel + ": tangents for a channel without values");
  ARMATURE_RETURN_IF_ERROR(CheckValues(tangents.in_tangents(), n, per_key, channel + ".inTangents", layout, e));
  ARMATURE_RETURN_IF_ERROR(CheckValues(tangents.out_tangents(), n, per_key, channel + ".outTangents", layout, e));
  track.in_tangents = convert(tangents.in_tangents());
  track.out_tangents = convert(tangents.out_tangents());
  return Status::Ok();
}

template <class V>
void SetTimes(Track<V>& track, const google::protobuf::RepeatedField<double>& times, Interpolation mode) {
  track.times.clear();
  for (double t : times) track.times.push_back(StoredKeyTime(t));
  track.interpolation = mode;
}

StatusOr<Interpolation> InterpolationOf(v1::Interpolation i, const EntryErrors& e) {
  ARMATURE_RETURN_IF_ERROR(ValidateEnum(i, v1::Interpolation_descriptor(), e.where() + ".interpolation"));
  switch (i) {
    case v1::STEP: return Interpolation::kStep;
    case v1::CUBIC: return Interpolation::kCubic;
    default: return Interpolation::kLinear;
  }
}

StatusOr<KeyedJoint> ReadEntry(const v1::JointKeys& in, int index, const Skeleton& skeleton,
                               const std::string& skeleton_name, bool may_delete, const Limits& limits) {
  const EntryErrors e(index, in.joint());
  if (in.joint().empty()) return e.Bad("joint is empty (name the joint the keys animate)");
  KeyedJoint out;
  out.joint = skeleton.Find(in.joint());
  if (out.joint < 0) {
    std::vector<std::string_view> names(skeleton.names.begin(), skeleton.names.end());
    return e.Bad("joint '" + in.joint() + "' is not on skeleton '" + skeleton_name + "'" +
                 DidYouMean(in.joint(), names));
  }
  ARMATURE_ASSIGN_OR_RETURN(auto mode, InterpolationOf(in.interpolation(), e));
  const bool cubic = mode == Interpolation::kCubic;
  const size_t n = static_cast<size_t>(in.times_size());
  const bool has_rot = !in.rotations().empty(), has_euler = !in.euler().empty();
  const bool has_t = !in.translations().empty(), has_s = !in.scales().empty();
  if (n == 0) {
    if (has_rot || has_euler || has_t || has_s) return e.Bad("values without times (give one time per key)");
    if (!may_delete)
      return e.Bad("no times: an entry without times deletes a stored or baked track, with merge or bake only");
    out.remove = true;
    return out;
  }
  if (static_cast<int64_t>(n) > limits.max_clip_frames)
    return Status::ResourceExhausted(e.where() + ": " + std::to_string(n) + " keys, over the limit of " +
                                     std::to_string(limits.max_clip_frames) + " keys per track (--max-clip-frames)");
  ARMATURE_RETURN_IF_ERROR(CheckTimes(in.times(), e));
  if (!has_rot && !has_euler && !has_t && !has_s)
    return e.Bad("times without values: give rotations, euler, translations or scales");
  if (has_rot && has_euler) return e.Bad("both rotations and euler: give one of them");
  if (!has_euler && !in.euler_order().empty()) return e.Bad("euler_order without euler angles");

  JointTrack& track = out.track;
  if (has_rot) {
    ARMATURE_RETURN_IF_ERROR(CheckValues(in.rotations(), n, 4, "rotations", "w, x, y, z", e));
    track.rotation.values = Quats(in.rotations());
    for (size_t k = 0; k < n; ++k) {
      const double norm = track.rotation.values[k].norm();
      if (std::abs(norm - 1) > kUnitTolerance)
        return e.BadKey(k, "rotation is not a unit quaternion (norm " + Num(norm) + ", tolerance 1e-3)");
      track.rotation.values[k].normalize();
    }
  } else if (has_euler) {
    ARMATURE_ASSIGN_OR_RETURN(auto order, ParseEulerOrder(in.euler_order(), e.where() + ".euler_order"));
    ARMATURE_RETURN_IF_ERROR(CheckValues(in.euler(), n, 3, "euler", "degrees, in euler_order", e));
    if (!in.rotation_tangents().in_tangents().empty() || !in.rotation_tangents().out_tangents().empty())
      return e.Bad("rotation_tangents are quaternion tangents: give rotations, not euler, with them");
    track.rotation.values.resize(n);
    for (size_t k = 0; k < n; ++k) {
      const double deg[3] = {in.euler(3 * k), in.euler(3 * k + 1), in.euler(3 * k + 2)};
      const double rad[3] = {deg[0] * M_PI / 180, deg[1] * M_PI / 180, deg[2] * M_PI / 180};
      track.rotation.values[k] = EulerToQuaternion(order, rad).normalized();
    }
  }
  if (has_rot || has_euler) SetTimes(track.rotation, in.times(), mode);
  if (has_t) {
    ARMATURE_RETURN_IF_ERROR(CheckValues(in.translations(), n, 3, "translations", "x, y, z", e));
    track.translation.values = Vec3s(in.translations());
    SetTimes(track.translation, in.times(), mode);
  }
  if (has_s) {
    ARMATURE_RETURN_IF_ERROR(CheckValues(in.scales(), n, 3, "scales", "x, y, z", e));
    track.scale.values = Vec3s(in.scales());
    SetTimes(track.scale, in.times(), mode);
  }
  auto given = [](const v1::KeyTangents& t) { return !t.in_tangents().empty() || !t.out_tangents().empty(); };
  ARMATURE_RETURN_IF_ERROR(ReadTangents(given(in.rotation_tangents()), in.rotation_tangents(), has_rot, n, 4,
                                        "rotation_tangents", "w, x, y, z", cubic, e, Quats, track.rotation));
  ARMATURE_RETURN_IF_ERROR(ReadTangents(given(in.translation_tangents()), in.translation_tangents(), has_t, n, 3,
                                        "translation_tangents", "x, y, z", cubic, e, Vec3s, track.translation));
  ARMATURE_RETURN_IF_ERROR(ReadTangents(given(in.scale_tangents()), in.scale_tangents(), has_s, n, 3, "scale_tangents",
                                        "x, y, z", cubic, e, Vec3s, track.scale));
  return out;
}

}  // namespace

double StoredKeyTime(double t) {
  float f = static_cast<float>(t);
  if (static_cast<double>(f) > t) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

StatusOr<std::vector<KeyedJoint>> KeyedJointsFromRequest(const v1::CreateClipRequest& request, const Skeleton& skeleton,
                                                         const std::string& skeleton_name, const Limits& limits) {
  std::vector<KeyedJoint> out;
  std::set<int> seen;
  for (int i = 0; i < request.tracks_size(); ++i) {
    auto entry =
        ReadEntry(request.tracks(i), i, skeleton, skeleton_name, request.merge() || request.has_bake(), limits);
    if (!entry.ok()) return entry.status();
    if (!seen.insert(entry->joint).second)
      return Status::InvalidArgument("tracks[" + std::to_string(i) + "] (joint '" + request.tracks(i).joint() +
                                     "'): a second entry for this joint (give each joint once)");
    out.push_back(std::move(*entry));
  }
  return out;
}

}  // namespace armature::server
