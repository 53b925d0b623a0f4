// Internal: one packed sample (three components, packed_track.h) read and
// dequantized for the sampling job. Its bits are read with one unaligned
// 64-bit load when they fit in it (up to 57 bits: 19 per component), which
// is nearly always, instead of one load per component; the values are those
// of ReadSample, (offset + scale · q) + i · slope per component, in float.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "anim/compression/packed_track.h"
#include "anim/compression/simd4.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"

namespace armature::compression_internal {

inline constexpr int kOneLoadBits = 57;  // 64 − 7: any bit offset within a byte

// Sample `i` (as a float: exact below 2^24), at bit `bit` of `data`, with `cursor`'s layout and
// dequantizer: x y z in lanes 0–2, lane 3 zero (the cursor's fourth offset,
// scale and slope).
ARMATURE_DECODE_INLINE v4 ReadKept(const uint8_t* data, size_t bit, float i, const TrackCursor& cursor) {
  const int b0 = cursor.bits[0], b1 = cursor.bits[1], b2 = cursor.bits[2];
  v4i q;
  if (cursor.total <= kOneLoadBits) [[likely]] {
    uint64_t word;
    std::memcpy(&word, data + (bit >> 3), sizeof word);
    word >>= bit & 7;
    q = v4i{static_cast<int>(word & ((uint64_t{1} << b0) - 1)),
            static_cast<int>((word >> b0) & ((uint64_t{1} << b1) - 1)),
            static_cast<int>((word >> (b0 + b1)) & ((uint64_t{1} << b2) - 1)), 0};
  } else {
    q = v4i{static_cast<int>(ReadBits(data, bit, b0)), static_cast<int>(ReadBits(data, bit + b0, b1)),
            static_cast<int>(ReadBits(data, bit + b0 + b1, b2)), 0};
  }
  // Below 2^23, so exact in float either way, as ReadSample's conversion.
  return (Load4(cursor.offset) + Load4(cursor.scale) * __builtin_convertvector(q, v4)) + Splat(i) * Load4(cursor.slope);
}

}  // namespace armature::compression_internal
