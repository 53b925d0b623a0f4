// Internal: an animated track while it is compressed: its values in its
// clip range, laid out per segment, and per segment the component a
// rotation drops, its target and its choice.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "anim/compression/clip_reference.h"
#include "anim/compression/segment_coder.h"

namespace armature::compression_internal {

struct TrackState {
  const TrackValues* values = nullptr;  // the reference's
  AnimatedTrack track;                  // what the runtime form keeps of it
  std::vector<uint8_t> dropped;         // per segment (rotations)
  std::vector<double> target;           // per segment
  std::vector<SegmentTrackChoice> choice;
  std::vector<double> chosen_at;  // per segment: the target its choice was made for (0: none yet)
  // per segment but the last: the next segment's first sample as decoded
  // (its last frame, shared: packed_track.h), set before it is chosen.
  std::vector<std::array<float, 4>> end;
};

// The track's clip range and dropped components.
TrackState MakeTrackState(const TrackValues& values, const FrameGrid& frames, double first_target);

// Sets `segment`'s shared end from the next segment's current choice.
void UpdateEnd(TrackState& state, const FrameGrid& frames, size_t segment);

// A segment's components in the track's clip range, in [0, 1]: worked out
// each time a segment is chosen or packed, not kept for the whole clip
// (23 bytes a joint-sample of CMU 01_01 during compression).
struct SegmentValues {
  std::array<double, (kSegmentFrames + 1) * 3> normalized;
};

// The frames of `segment` as the segment coder reads them; its normalized
// values in `values`, which it points into.
SegmentTrackInput SegmentInput(const TrackState& state, const FrameGrid& frames, size_t segment, SegmentValues& values);

}  // namespace armature::compression_internal
