// Internal: the clip as stored, sampled at its frames (the reference the
// error is measured against), its tracks' values, and how far a value error
// of each track moves the virtual points (its lever).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/anim/compression/shell_error.h"
#include "anim/compression/packed_track.h"

namespace armature::compression_internal {

// One source track over every frame: 4 values per frame (rotations x y z w
// as stored, vectors x y z 0) and its lever.
struct TrackValues {
  uint16_t joint = 0;
  TrackKind kind = TrackKind::kRotation;
  std::vector<double> raw;
  double lever = 1;                   // over the clip
  std::vector<double> segment_lever;  // over each segment's frames
};

// The reference keeps the source's tracks only, and rebuilds a frame's
// local and world poses from them when it is measured: keeping both poses
// of every frame cost about 160 bytes per joint-sample during compression
// (the compressor's peak heap was 245 bytes a joint-sample on CMU 01_01,
// 4 times the source clip; 50 now).
struct ClipReference {
  FrameGrid frames;
  const Skeleton* skeleton = nullptr;
  std::vector<TrackValues> tracks;  // every track the source has, joints in order, then rotation, translation, scale
  // Per joint: the farthest virtual point of it or its descendants (world
  // units), its parent's largest world scale, its smallest local scale.
  std::vector<double> reach, parent_scale, min_scale;
  std::vector<double> segment_reach;  // the same per segment: segments × joints
  // The largest local translation or scale component in magnitude, rest
  // values included; infinity for one that is not finite.
  double largest_magnitude = 0;
};

StatusOr<ClipReference> SampleReference(const Clip& clip, const FrameGrid& frames, double shell_distance);

// Frame `f`'s world poses (joints) as SampleClip and ComposeWorldQvv gave
// them, rebuilt from the tracks into `local` (joints), the same values.
void ReferenceWorld(const ClipReference& reference, size_t f, std::span<Trs> local, std::span<WorldQvv> world);

// 2·sin(angle/2) of the rotation between unit `raw` and `q` (x y z w, any
// length): a point at distance 1 moves that far. From the chord |raw − q̂|,
// which keeps its precision for tiny angles where 1 − dot² does not.
double RotationChord(const double* raw, const double* q);

// Its square, from a float rotation, without square roots but |q|'s: for
// the segment coder's inner loop. 1 − |dot|/|q| keeps double's precision.
inline double RotationChordSquared(const double* raw, const float* q) {
  double dot = 0, norm2 = 0;
  for (int c = 0; c < 4; ++c) {
    dot += raw[c] * q[c];
    norm2 += static_cast<double>(q[c]) * q[c];
  }
  const double d2 = std::max(0.0, 2 - 2 * std::abs(dot) / std::sqrt(norm2));  // |raw − q̂|² = 4·sin²(angle/4)
  return 4 * d2 * (1 - d2 / 4);  // (2·sin(angle/2))² = 16·sin²(angle/4)·cos²(angle/4)
}

// Whether `value` can replace every frame of `track` with no displacement
// above `limit`: false at the first frame above it.
bool ConstantFits(const TrackValues& track, const float* value, double limit);

}  // namespace armature::compression_internal
