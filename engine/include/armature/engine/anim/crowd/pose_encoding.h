// A crowd's compact wire form of one local pose (issue 31): every joint's
// rotation as smallest-three in 48 bits (the largest component's index in 2
// bits, the other three in 15 bits each over [-1/√2, 1/√2], one bit spare),
// then a float32 translation for each joint whose clip animates (varies) its
// translation, then likewise a float32 scale for each joint whose scale
// varies. Everything else, the constant translations and scales, is the
// layout's base pose, sent once per clip. With a root mover and 31
// joints that is 6.4 bytes a joint.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "armature/base/status.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/math/transform.h"

namespace armature {

inline constexpr size_t kEncodedRotationBytes = 6;
inline constexpr size_t kEncodedTranslationBytes = 12;
// The worst rotation angle (radians) the rotation quantization adds; see
// pose_encoding.cc for its derivation: 4·asin(√3·e) with e = √2/(2·32767).
double MaxEncodedRotationError();

// What a clip's poses need on the wire: its joints, the joints whose
// translation or scale varies (sent each frame, ascending), and the base pose
// the decoder starts from (the pose at time 0: constant translations, scales).
struct PoseLayout {
  uint32_t joints = 0;
  std::vector<uint16_t> translated, scaled;
  std::vector<Trs> base;

  size_t EncodedSize() const {
    return joints * kEncodedRotationBytes + (translated.size() + scaled.size()) * kEncodedTranslationBytes;
  }
};

// The layout of a compressed clip's poses (samples the clip once at time 0).
StatusOr<PoseLayout> LayoutOfClip(const CompressedClip& clip);

// 48 bits of smallest-three, and back (a unit quaternion; q and −q alike).
uint64_t EncodeRotation(const Eigen::Quaterniond& q);
Eigen::Quaterniond DecodeRotation(uint64_t bits);
// The same from a float rotation (x y z w; ClipSamplingFloatJob's lanes).
uint64_t EncodeRotation(const float* xyzw);

// Writes layout.EncodedSize() bytes of `pose` (size layout.joints) to `out`.
// No allocation.
void EncodePose(const PoseLayout& layout, std::span<const Trs> pose, uint8_t* out);
// The same from float lanes (ClipSamplingFloatJob's, sized to the layout).
void EncodePose(const PoseLayout& layout, const FloatPose& pose, uint8_t* out);
// Reads one pose; INVALID_ARGUMENT when the sizes disagree.
Status DecodePose(const PoseLayout& layout, std::span<const uint8_t> bytes, std::span<Trs> pose);

}  // namespace armature
