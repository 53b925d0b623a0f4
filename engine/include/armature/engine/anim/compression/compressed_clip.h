// A clip's compressed runtime form under a per-clip error bound (issue 30),
// written after ACL's ideas: default (rest) and constant tracks dropped to
// one value or none, per-clip and per-segment range reduction, a bit rate per
// track and segment chosen against the error, and, where ACL keeps every
// frame, a sample stride per track and segment (interpolated between). The
// measured error (ACL's virtual points, shell_error.h) never exceeds the bound:
// a clip that cannot meet it is kept exact, with a warning. `exact` keeps the
// stored keys bit for bit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "armature/base/status.h"
#include "armature/engine/anim/clip.h"
#include "armature/engine/anim/compression/compressed_weights.h"
#include "armature/engine/anim/compression/error_bound.h"
#include "armature/engine/anim/compression/shell_error.h"
#include "armature/engine/anim/skeleton.h"

namespace armature {

enum class TrackKind : uint8_t { kRotation, kTranslation, kScale };

// A track whose value does not change: rotations x y z w, vectors x y z.
struct ConstantTrack {
  uint16_t joint = 0;
  TrackKind kind = TrackKind::kRotation;
  float value[4] = {0, 0, 0, 1};
};

// A track with samples in the packed segments: its clip range per component.
struct AnimatedTrack {
  uint16_t joint = 0;
  TrackKind kind = TrackKind::kRotation;
  uint8_t dropped = 3;  // rotations: the component (x y z w) rebuilt from the other three
  float min[3] = {0, 0, 0};
  float extent[3] = {0, 0, 0};
};

struct CompressedClip {
  // Unique per CompressClip call: a sampling context tells a clip from a
  // later one at the same address.
  uint64_t serial = 0;
  std::shared_ptr<const Skeleton> skeleton;
  double duration = 0;
  // The source's Clip::frame_time (0: key-framed), frame_count and
  // default_interpolation, for listings once the source has left memory.
  double source_frame_time = 0;
  size_t source_frame_count = 0;
  Interpolation source_interpolation = Interpolation::kLinear;
  FrameGrid frames;         // the frames the bound holds at (the source's, or 30 fps at least)
  ClipPrecision precision;  // as asked (exact also when the bound could not be met)
  ErrorBound bound;         // in the skeleton's units
  ClipError error;          // measured against the source at every frame
  std::string warning;      // why a bound was not kept (then stored exact)
  // Per joint, what the source animates (bit 0 rotation, 1 translation, 2
  // scale): what a joint map replaces on another skeleton.
  std::vector<uint8_t> animated_parts;

  // exact: the stored keys, sampled as SampleClip does.
  std::shared_ptr<const Clip> exact_keys;

  // lossy: joints not named here keep the rest pose.
  std::vector<ConstantTrack> constants;
  std::vector<AnimatedTrack> animated;
  std::vector<uint32_t> segment_offsets;  // byte offset of each segment in `data`
  std::vector<uint8_t> data;              // per segment: codes, ranges, then samples (packed_track.h)

  // lossy: the morph weights, per mesh, within WeightBound(bound)
  // (compressed_weights.h; exact: as stored, in exact_keys).
  std::vector<CompressedWeights> weights;
  double weight_error = 0;  // lossy: the largest weight error measured over the frames

  bool exact() const { return exact_keys != nullptr; }
  // The morph weights of `mesh` (`targets` of them) at clip time `time`
  // (already wrapped) into `out`; false when the clip has none for it.
  bool SampleMorphWeights(std::string_view mesh, size_t targets, double time,
                          const std::optional<Interpolation>& interpolation, std::span<double> out) const;
  // Bytes of the runtime form (stored keys for exact, in their double form).
  size_t ByteSize() const;
  // ByteSize over joints × frames.
  double BytesPerJointSample() const;
};

// Compresses a valid clip. INVALID_ARGUMENT naming `precision` for a bound
// that is 0, negative, NaN or above 10 cm.
StatusOr<std::shared_ptr<const CompressedClip>> CompressClip(std::shared_ptr<const Clip> clip,
                                                             const ClipPrecision& precision = {});

// Joint-samples (frames × joints) past which CompressClip does not resample
// a clip up to 30 frames a second: the bound is checked on a reference of
// two transforms (about 200 bytes) per joint-sample, so a few keys spread
// over a long time (a BVH frame time of a year) would cost memory without
// bound. Such a clip is kept exact, with a warning.
inline constexpr double kMaxResampledJointSamples = 1 << 21;

// The frames a clip is compressed at: its own when at least 30 per second,
// else each of its intervals split evenly to reach 30 (its keys stay frames);
// nullopt when that split would pass kMaxResampledJointSamples.
std::optional<FrameGrid> CompressionFrames(const Clip& clip);

}  // namespace armature
