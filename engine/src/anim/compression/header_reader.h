// Internal: a segment's header (packed_track.h) read one track after another
// into the sampling job's cursors, written in place (a cursor built aside
// and copied stalls on store forwarding). The layout and dequantizer are
// FillLayout's and FillDequantizer's, computed for the three components at
// once in one vector, with the same float operations, so the same values.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "anim/compression/packed_track.h"
#include "anim/compression/simd4.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/compression/compressed_clip.h"

namespace armature::compression_internal {

class HeaderReader {
 public:
  HeaderReader(const CompressedClip& clip, size_t segment) : clip_(clip) {
    const size_t segments = clip.segment_offsets.size();
    data_ = clip.data.data() + clip.segment_offsets[segment];
    back_ = clip.data.data() +
            (segment + 1 < segments ? clip.segment_offsets[segment + 1] : clip.data.size() - kReadPadding);
    const size_t start = segment * kSegmentFrames;
    intervals_ = std::min(kSegmentFrames, clip.frames.count - 1 - start);
    shares_end_ = segment + 1 < segments;
    bit_ = clip.animated.size() * 8;
  }

  const uint8_t* data() const { return data_; }

  // Track `t`'s cursor (tracks in order, each once); its dequantizer only when `full`.
  void Next(size_t t, TrackCursor& cursor, bool full = true) {
    const AnimatedTrack& track = clip_.animated[t];
    const TrackCode code = kCodes[data_[t]];
    cursor.dropped = track.dropped == kDroppedPerSegment ? *--back_ : track.dropped;
    const v4 extent{track.extent[0], track.extent[1], track.extent[2], 0.f};
    v4 low = Splat(0.f), high = Splat(1.f), range_extent = Splat(255.f);  // unranged: the whole clip range
    if (code.ranged) {
      const uint8_t* range = back_ -= kRangeBytes;
      range_extent = v4{static_cast<float>(range[3]), static_cast<float>(range[4]), static_cast<float>(range[5]), 0.f};
      low = v4{static_cast<float>(range[0]), static_cast<float>(range[1]), static_cast<float>(range[2]), 0.f} *
            Splat(1.f / 255);
      high = range_extent * Splat(1.f / 255);
    }
    // FillLayout: the widest component (by float exponent) gets the code's bits.
    const v4i exponent = (reinterpret_cast<v4i>(extent * range_extent) >> 23) & 0xff;
    const int widest = std::max(std::max(exponent[0], exponent[1]), std::max(exponent[2], 0));
    const v4i bits = static_cast<int>(code.bits) - (widest - exponent);
    const v4i clamped = bits < 1 ? v4i{1, 1, 1, 1} : bits;
    cursor.bits[0] = static_cast<uint8_t>(clamped[0]);
    cursor.bits[1] = static_cast<uint8_t>(clamped[1]);
    cursor.bits[2] = static_cast<uint8_t>(clamped[2]);
    cursor.total = static_cast<uint8_t>(clamped[0] + clamped[1] + clamped[2]);
    if (full) {  // FillDequantizer
      const v4 inverse_max{kInverseMax[clamped[0]], kInverseMax[clamped[1]], kInverseMax[clamped[2]], 0.f};
      const v4 min{track.min[0], track.min[1], track.min[2], 0.f};
      Store4(cursor.offset, min + extent * low);
      Store4(cursor.scale, extent * high * inverse_max);
    }
    cursor.bit = static_cast<uint32_t>(bit_);
    cursor.stride_log = code.stride_log;
    bit_ += static_cast<size_t>(cursor.total) * StoredSamples(code.stride_log, intervals_, shares_end_);
  }

 private:
  const CompressedClip& clip_;
  const uint8_t* data_;
  const uint8_t* back_;
  size_t intervals_ = 0, bit_ = 0;
  bool shares_end_ = false;
};

}  // namespace armature::compression_internal
