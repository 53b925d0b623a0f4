// Smallest-three: a unit quaternion's largest component |m| ≥ 1/2, so the
// other three lie in [-1/√2, 1/√2] (each ≤ √(1 − m²) ≤ √(1/2)) and rebuild m
// as √(1 − a² − b² − c²) once m is made positive (q and −q are one rotation).
//
// The worst error. 15 bits over a span of √2 round each component by at most
// e = √2 / (2·32767) ≈ 2.158e-5, so the three kept move by |Δv| ≤ √3·e. The
// rebuilt one moves by |Δm| = |v·Δv| / m ≤ (√3/2)(√3·e)/(1/2) = 3e (|v| ≤ √3/2
// since m ≥ 1/2). The 4-D chord between q and the decoded q' is then at most
// √(3e² + 9e²) = 2√3·e, their angle on the sphere 2·asin(√3·e), and the
// rotation angle, twice that: 4·asin(√3·e) ≈ 1.495e-4 rad (0.0086°).
#include "armature/engine/anim/crowd/pose_encoding.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "armature/engine/anim/compression/clip_sampling_job.h"

namespace armature {
namespace {

constexpr int kComponentBits = 15;
constexpr uint32_t kComponentMax = (1u << kComponentBits) - 1;  // 32767 steps over the span
const double kHalfSpan = std::sqrt(0.5);

const double kQuantumsPerUnit = kComponentMax / (2 * kHalfSpan);

// Rounds v ∈ [-1/√2, 1/√2] to its step: no branches (max, min, and the
// integer part of x + 0.5, which rounds half up for x ≥ 0) and no division,
// for the crowd's hot path.
inline uint32_t Quantize(double v) {
  double x = (v + kHalfSpan) * kQuantumsPerUnit;
  x = x > 0.0 ? x : 0.0;
  x = x < kComponentMax ? x : static_cast<double>(kComponentMax);
  return static_cast<uint32_t>(x + 0.5);
}

// The kept components of smallest-three, by the index of the dropped one.
constexpr uint8_t kKept[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};

// Smallest-three of x y z w floats (the float path: the same bits as the
// double one for the same values).
inline uint64_t EncodeFloatRotation(const float* xyzw) {
  int largest = 0;
  float most = std::abs(xyzw[0]);
  for (int i = 1; i < 4; ++i) {  // selects, no branches
    const float a = std::abs(xyzw[i]);
    largest = a > most ? i : largest;
    most = a > most ? a : most;
  }
  const double sign = xyzw[largest] < 0 ? -1.0 : 1.0;
  const uint8_t* kept = kKept[largest];
  return static_cast<uint64_t>(largest) | static_cast<uint64_t>(Quantize(sign * xyzw[kept[0]])) << 2 |
         static_cast<uint64_t>(Quantize(sign * xyzw[kept[1]])) << (2 + kComponentBits) |
         static_cast<uint64_t>(Quantize(sign * xyzw[kept[2]])) << (2 + 2 * kComponentBits);
}

double Dequantize(uint32_t q) { return static_cast<double>(q) / kComponentMax * (2 * kHalfSpan) - kHalfSpan; }

void StoreBytes(uint64_t bits, size_t count, uint8_t* out) {
  for (size_t i = 0; i < count; ++i) out[i] = static_cast<uint8_t>(bits >> (8 * i));
}

uint64_t LoadBytes(const uint8_t* in, size_t count) {
  uint64_t bits = 0;
  for (size_t i = 0; i < count; ++i) bits |= static_cast<uint64_t>(in[i]) << (8 * i);
  return bits;
}

uint8_t* StoreVector(const Eigen::Vector3d& v, uint8_t* out) {
  const float f[3] = {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
  std::memcpy(out, f, sizeof f);  // little-endian hosts only, as the rest of the wire
  return out + kEncodedTranslationBytes;
}

uint8_t* StoreFloats(const float* v, uint8_t* out) {
  std::memcpy(out, v, kEncodedTranslationBytes);
  return out + kEncodedTranslationBytes;
}

const uint8_t* LoadVector(const uint8_t* in, Eigen::Vector3d& v) {
  float f[3];
  std::memcpy(f, in, sizeof f);
  v = Eigen::Vector3d(f[0], f[1], f[2]);
  return in + kEncodedTranslationBytes;
}

// The joints whose translation (or scale) takes more than one value in the clip.
std::vector<uint16_t> VaryingJoints(const CompressedClip& clip, TrackKind kind) {
  std::vector<uint8_t> varies(clip.skeleton->size(), 0);
  if (clip.exact()) {
    for (size_t j = 0; j < clip.exact_keys->joints.size(); ++j) {
      const JointTrack& joint = clip.exact_keys->joints[j];
      const Vec3Track& t = kind == TrackKind::kTranslation ? joint.translation : joint.scale;
      for (size_t k = 1; k < t.values.size() && !varies[j]; ++k) varies[j] = t.values[k] != t.values[0];
    }
  } else {
    for (const AnimatedTrack& track : clip.animated)
      if (track.kind == kind) varies[track.joint] = 1;
  }
  std::vector<uint16_t> joints;
  for (size_t j = 0; j < varies.size(); ++j)
    if (varies[j]) joints.push_back(static_cast<uint16_t>(j));
  return joints;
}

}  // namespace

double MaxEncodedRotationError() {
  const double e = std::sqrt(2.0) / (2.0 * kComponentMax);
  return 4 * std::asin(std::sqrt(3.0) * e);
}

StatusOr<PoseLayout> LayoutOfClip(const CompressedClip& clip) {
  if (!clip.skeleton) return Status::InvalidArgument("pose layout: the clip has no skeleton");
  if (clip.skeleton->size() > 65535)
    return Status::InvalidArgument("pose layout: " + std::to_string(clip.skeleton->size()) + " joints, at most 65535");
  PoseLayout layout;
  layout.joints = static_cast<uint32_t>(clip.skeleton->size());
  layout.translated = VaryingJoints(clip, TrackKind::kTranslation);
  layout.scaled = VaryingJoints(clip, TrackKind::kScale);
  layout.base.resize(layout.joints);
  ARMATURE_RETURN_IF_ERROR((ClipSamplingJob{&clip, 0.0, WrapMode::kClamp, nullptr, layout.base, std::nullopt}.Run()));
  return layout;
}

uint64_t EncodeRotation(const Eigen::Quaterniond& q) {
  const double c[4] = {q.x(), q.y(), q.z(), q.w()};
  int largest = 0;
  for (int i = 1; i < 4; ++i)
    if (std::abs(c[i]) > std::abs(c[largest])) largest = i;
  const double sign = c[largest] < 0 ? -1.0 : 1.0;
  uint64_t bits = static_cast<uint64_t>(largest);
  int shift = 2;
  for (int i = 0; i < 4; ++i) {
    if (i == largest) continue;
    bits |= static_cast<uint64_t>(Quantize(sign * c[i])) << shift;
    shift += kComponentBits;
  }
  return bits;
}

uint64_t EncodeRotation(const float* xyzw) { return EncodeFloatRotation(xyzw); }

Eigen::Quaterniond DecodeRotation(uint64_t bits) {
  const int largest = static_cast<int>(bits & 3);
  double c[4];
  double sum = 0;
  int shift = 2;
  for (int i = 0; i < 4; ++i) {
    if (i == largest) continue;
    c[i] = Dequantize(static_cast<uint32_t>(bits >> shift) & kComponentMax);
    sum += c[i] * c[i];
    shift += kComponentBits;
  }
  c[largest] = std::sqrt(sum < 1 ? 1 - sum : 0.0);
  Eigen::Quaterniond q(c[3], c[0], c[1], c[2]);
  q.normalize();  // a rounding's worth: keeps the decoded rotation unit
  return q;
}

void EncodePose(const PoseLayout& layout, std::span<const Trs> pose, uint8_t* out) {
  for (uint32_t j = 0; j < layout.joints; ++j, out += kEncodedRotationBytes)
    StoreBytes(EncodeRotation(pose[j].rotation), kEncodedRotationBytes, out);
  for (uint16_t j : layout.translated) out = StoreVector(pose[j].translation, out);
  for (uint16_t j : layout.scaled) out = StoreVector(pose[j].scale, out);
}

void EncodePose(const PoseLayout& layout, const FloatPose& pose, uint8_t* out) {
  for (uint32_t j = 0; j < layout.joints; ++j, out += kEncodedRotationBytes) {
    const uint64_t bits = EncodeFloatRotation(&pose.rotations[4 * j]);
    const auto low = static_cast<uint32_t>(bits);
    const auto high = static_cast<uint16_t>(bits >> 32);
    std::memcpy(out, &low, 4);  // little-endian hosts only, as the rest of the wire
    std::memcpy(out + 4, &high, 2);
  }
  for (uint16_t j : layout.translated) out = StoreFloats(&pose.translations[3 * j], out);
  for (uint16_t j : layout.scaled) out = StoreFloats(&pose.scales[3 * j], out);
}

Status DecodePose(const PoseLayout& layout, std::span<const uint8_t> bytes, std::span<Trs> pose) {
  if (bytes.size() != layout.EncodedSize() || pose.size() != layout.joints || layout.base.size() != layout.joints)
    return Status::InvalidArgument("pose decoding: " + std::to_string(bytes.size()) + " bytes for a layout of " +
                                   std::to_string(layout.EncodedSize()) + " (" + std::to_string(layout.joints) +
                                   " joints) into " + std::to_string(pose.size()) + " transforms");
  const uint8_t* in = bytes.data();
  for (uint32_t j = 0; j < layout.joints; ++j, in += kEncodedRotationBytes) {
    pose[j] = layout.base[j];
    pose[j].rotation = DecodeRotation(LoadBytes(in, kEncodedRotationBytes));
  }
  for (uint16_t j : layout.translated) in = LoadVector(in, pose[j].translation);
  for (uint16_t j : layout.scaled) in = LoadVector(in, pose[j].scale);
  return Status::Ok();
}

}  // namespace armature
