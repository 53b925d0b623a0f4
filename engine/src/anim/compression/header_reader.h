// Internal: a segment's header (packed_track.h) read one track after another
// into the sampling job's cursors, written in place (a cursor built aside
// and copied stalls on store forwarding). The layout and dequantizer are
// FillLayout's and FillDequantizer's, computed for the three components at
// once in one vector, with the same float operations, so the same values.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "anim/compression/packed_track.h"
#include "anim/compression/simd4.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/compression/compressed_clip.h"

namespace armature::compression_internal {

class HeaderReader {
 public:
  ARMATURE_DECODE_INLINE HeaderReader(const CompressedClip& clip, size_t segment) : clip_(clip) {
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
  ARMATURE_DECODE_INLINE void Next(size_t t, TrackCursor& cursor, bool full = true) {
    const AnimatedTrack& track = clip_.animated[t];
    const TrackCode code = kCodes[data_[t]];
    cursor.dropped = track.dropped == kDroppedPerSegment ? *--back_ : track.dropped;
    back_ -= code.ranged ? kRangeBytes : 0;
    const uint8_t* range = code.ranged ? back_ : kUnranged;
    back_ -= code.sloped ? kSlopeBytes : 0;
    const v4 extent{track.extent[0], track.extent[1], track.extent[2], 0.f};
    v4 low, range_extent;
    RangeOf(range, low, range_extent);
    const int bits = Layout(code.bits, extent * range_extent, cursor);
    if (full) {  // FillDequantizer: unranged, low 0 and extent 1 (kUnranged's step 0)
      const v4 inverse_max{kInverseMax[bits & 0xff], kInverseMax[(bits >> 8) & 0xff], kInverseMax[(bits >> 16) & 0xff],
                           0.f};
      const v4 min{track.min[0], track.min[1], track.min[2], 0.f};
      Store4(cursor.offset, min + extent * (low * Splat(kInverseRangeLowMax)));
      Store4(cursor.scale, extent * range_extent * inverse_max);
      const v4 drift = SlopeOf(code.sloped ? back_ : kUnranged) * Splat(kSlopeStep);
      Store4(cursor.slope, extent * drift);
    }
    cursor.bit = static_cast<uint32_t>(bit_);
    cursor.stride_log = code.stride_log;
    bit_ += static_cast<size_t>(static_cast<unsigned>(bits) >> 24) *
            StoredSamples(code.stride_log, intervals_, shares_end_);
  }

 private:
  // The whole clip range, as a segment range: low 0, extent step 0 (8
  // bytes: read as one word). Also no slope.
  static constexpr uint8_t kUnranged[8] = {};

  // A slope's three steps (SlopeSteps) as floats, lane 3: 0. Its bytes sit
  // before the range's, so the 4-byte read stays in the data.
  ARMATURE_DECODE_INLINE static v4 SlopeOf(const uint8_t* slope) {
#if defined(__SSE2__)
    uint32_t word;
    std::memcpy(&word, slope, sizeof word);
    __m128i steps = _mm_cvtsi32_si128(static_cast<int>(word & 0xffffffu));
    steps = _mm_unpacklo_epi8(steps, steps);  // each byte to the top of a 32-bit lane, then sign-extended down
    steps = _mm_srai_epi32(_mm_unpacklo_epi16(steps, steps), 24);
    return _mm_cvtepi32_ps(steps);
#else
    return v4{static_cast<float>(SlopeSteps(slope, 0)), static_cast<float>(SlopeSteps(slope, 1)),
              static_cast<float>(SlopeSteps(slope, 2)), 0.f};
#endif
  }

  // A segment range's low ends (integers, as floats) and extents
  // (RangeExtent), lane 3: 0. The range sits before the segment's end or
  // the clip's padding, so its 8-byte read stays in the data.
  ARMATURE_DECODE_INLINE static void RangeOf(const uint8_t* range, v4& low, v4& extent) {
    extent = v4{RangeExtent(range, 0), RangeExtent(range, 1), RangeExtent(range, 2), 0.f};
#if defined(__SSE2__)
    uint64_t word;
    std::memcpy(&word, range, sizeof word);
    const __m128i fields = _mm_unpacklo_epi16(_mm_cvtsi64_si128(static_cast<long long>(word)), _mm_setzero_si128());
    const __m128i mask = _mm_set_epi32(0, kRangeLowMax, kRangeLowMax, kRangeLowMax);
    low = _mm_cvtepi32_ps(_mm_and_si128(fields, mask));  // RangeLow of the three, in one vector
#else
    low = v4{static_cast<float>(RangeLow(range, 0)), static_cast<float>(RangeLow(range, 1)),
             static_cast<float>(RangeLow(range, 2)), 0.f};
#endif
  }

  // FillLayout: the widest component (by float exponent of `scaled`, the
  // clip extent times the range extent) gets `bits`, a narrower one a
  // bit less per halving, at least 1. Writes the cursor's bits and total;
  // returns the three bits as bytes 0–2 of an int.
  static int Layout(int bits, v4 scaled, TrackCursor& cursor) {
    const v4i exponent = (reinterpret_cast<v4i>(scaled) >> 23) & 0xff;  // lane 3: 0
#if defined(__SSE2__)
    const v4i once =
        reinterpret_cast<v4i>(_mm_shuffle_epi32(reinterpret_cast<__m128i>(exponent), _MM_SHUFFLE(2, 3, 0, 1)));
    const v4i pairs = exponent > once ? exponent : once;  // max(e0, e1) twice, max(e2, 0) twice
    const v4i twice =
        reinterpret_cast<v4i>(_mm_shuffle_epi32(reinterpret_cast<__m128i>(pairs), _MM_SHUFFLE(1, 0, 3, 2)));
    const v4i all_widest = pairs > twice ? pairs : twice;
    v4i out = bits - (all_widest - exponent);
    out = out < 1 ? v4i{1, 1, 1, 1} : out;
    out[3] = out[0] + out[1] + out[2];
    const __m128i packed =
        _mm_packus_epi16(_mm_packs_epi32(reinterpret_cast<__m128i>(out), _mm_setzero_si128()), _mm_setzero_si128());
    const int word = _mm_cvtsi128_si32(packed);
#else
    const int widest = std::max(std::max(exponent[0], exponent[1]), std::max(exponent[2], 0));
    int word = 0, total = 0;
    for (int c = 0; c < 3; ++c) {
      const int b = std::max(bits - (widest - exponent[c]), 1);
      word |= b << (8 * c);
      total += b;
    }
    word |= total << 24;
#endif
    static_assert(offsetof(TrackCursor, total) == offsetof(TrackCursor, bits) + 3);
    std::memcpy(reinterpret_cast<unsigned char*>(&cursor) + offsetof(TrackCursor, bits), &word, sizeof word);
    return word;
  }

  const CompressedClip& clip_;
  const uint8_t* data_;
  const uint8_t* back_;
  size_t intervals_ = 0, bit_ = 0;
  bool shares_end_ = false;
};

}  // namespace armature::compression_internal
