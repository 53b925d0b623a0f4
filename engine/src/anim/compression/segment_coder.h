// Internal: one animated track in one segment, quantized and chosen. The
// choice (bit rate, sample stride, segment range or not, drifting or not) is the cheapest in
// bits whose decoded frames all stay within a displacement target, the
// error measured as the sampling job will decode (packed_track.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "armature/engine/anim/compression/compressed_clip.h"
#include "anim/compression/packed_track.h"

namespace armature::compression_internal {

// A track's frames in one segment.
struct SegmentTrackInput {
  TrackKind kind = TrackKind::kRotation;
  int dropped = 3;                     // rotations: the component rebuilt
  size_t intervals = 0;                // frames − 1
  std::span<const double> raw;         // (intervals + 1) × 4: x y z w, or x y z 0, as stored
  std::span<const double> normalized;  // (intervals + 1) × 3: quantized components in the clip range, in [0, 1]
  const float* clip_min = nullptr;     // 3
  const float* clip_extent = nullptr;  // 3
  // World displacement per unit of value error: rotations per unit of
  // chord (2·sin(angle/2)), vectors per unit of distance.
  double lever = 1;
  // The next segment's first sample as decoded (x y z w, or x y z), when
  // this segment shares its last frame with it (packed_track.h); else null.
  const float* end = nullptr;
  int hint_bits = 0;         // bits likely to be near the answer (a neighbour's), or 0
  int hint_stride_log = -1;  // the stride the hint is for
};

struct SegmentTrackChoice {
  uint8_t code = 0;
  uint8_t range[kRangeBytes] = {};
  uint8_t slope[kSlopeBytes] = {};  // when sloped (kCodes)
  size_t bits = 0;                  // samples' bits, plus the range's and slope's when there are
};

// The bytes a choice keeps after the samples (its range and slope).
inline size_t TailBytes(const SegmentTrackChoice& choice) {
  const TrackCode code = kCodes[choice.code];
  return (code.ranged ? kRangeBytes : 0) + (code.sloped ? kSlopeBytes : 0);
}

// The cheapest choice within `target`, or nothing when 23 bits on every
// frame do not reach it.
std::optional<SegmentTrackChoice> ChooseSegmentTrack(const SegmentTrackInput& in, double target);

// The choice's first sample as the sampling job decodes it (x y z w, or x y z).
void DecodeFirstSample(const SegmentTrackInput& in, const SegmentTrackChoice& choice, float* out);

// Writes the choice's samples at bit `offset` of `data`.
void PackSegmentTrack(const SegmentTrackInput& in, const SegmentTrackChoice& choice, uint8_t* data, size_t offset);

}  // namespace armature::compression_internal
