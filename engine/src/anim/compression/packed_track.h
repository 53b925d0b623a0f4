// Internal: the packed form of a compressed clip's animated tracks, shared by
// the compressor and the sampling job.
//
// Frames are cut into segments of kSegmentFrames intervals. In each segment
// every animated track stores samples of its three components every
// `stride` frames (rotations: three of x y z w, the fourth kept ≥ 0 and
// rebuilt as √(1 − a² − b² − c²); the dropped one is the track's largest in
// magnitude over the clip, or over each segment when none stays far from 0
// (a root turning round), not always w as in ACL, so a joint turning
// through 180° keeps its precision where w passes 0),
// both ends included, as `bits`-bit integers in the track's clip range and,
// optionally, a segment range (16 bits per component: low end and extent) inside it.
// A segment range that keeps every frame may also drift: a slope (a signed
// byte per component) moves the range along the samples, so a component
// that moves steadily through the segment is quantized in the narrow band
// around its line, not across all it covers. On CMU 01_01 half the
// track-segments drift (2,504 of 4,816), and the clip is 7.2% smaller
// (175,448 bytes to 162,828: 2.074 to 1.926 bytes a joint-sample).
// Frames between samples are interpolated (lerp, nlerp for rotations); at
// the default bound most of CMU's tracks still keep every frame at 120 fps
// (4,409 of 4,816 track-segments of 01_01). A track's choice in a
// segment is one byte (kCodes); a segment is laid out as every track's
// code, then every track's samples, then from the segment's end backwards,
// per track in order, its dropped component (per-segment rotations), its
// range (when ranged) and its slope (when sloped), so all are found without
// a first pass; ACL chooses the bit rate per track and segment too, but
// keeps every frame, and its ranges do not drift.
//
// A segment's last frame is the next segment's first: a segment that has a
// next one does not store it, and its last interval interpolates toward the
// next segment's first sample, decoded as that segment decodes it. So
// sampling is continuous across a boundary (each segment quantizing the
// shared frame in its own range left a step), and each track keeps one
// sample fewer per segment. The clip's last segment stores its last frame.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#if defined(__SSE__)
#include <immintrin.h>
#endif

namespace armature::compression_internal {

inline constexpr size_t kSegmentFrames = 16;
inline constexpr int kMinBits = 3, kMaxBits = 23, kRateCount = kMaxBits - kMinBits + 1;
inline constexpr int kStrideLogs = 5;     // strides 1, 2, 4, 8, 16
inline constexpr size_t kRangeBytes = 6;  // segment range: low and extent bytes of 3 components
inline constexpr size_t kSlopeBytes = 3;  // a drifting range's slope: a signed byte per component
inline constexpr size_t kReadPadding = 8;
// AnimatedTrack::dropped when each segment names its own (one byte before its range).
inline constexpr uint8_t kDroppedPerSegment = 4;  // bytes after the data, so 64-bit reads never leave it

// Segments of a clip of `frames` frames (the last holds the rest; none for one frame).
inline size_t SegmentCount(size_t frames) { return frames < 2 ? 0 : (frames - 2) / kSegmentFrames + 1; }

// A segment range: per component 16 bits (little-endian), its low end in
// the low kRangeLowBits, in steps of 1/kRangeLowMax of the clip range, and
// its extent in the rest: a step down a scale of kRangeStepsPerOctave steps
// per halving from the whole clip range (kRangeExtents). At 120 fps half of
// CMU 01_01's segment ranges are under 16/255 of the clip's, where a byte
// for each end, rounded outward, widened them most; this split measured
// best of eight (1% smaller on CMU 01_01).
inline constexpr int kRangeLowBits = 9;
inline constexpr uint32_t kRangeLowMax = (1u << kRangeLowBits) - 1;
inline constexpr float kInverseRangeLowMax = 1.f / static_cast<float>(kRangeLowMax);
inline constexpr int kRangeExtentSteps = 1 << (16 - kRangeLowBits);
inline constexpr int kRangeStepsPerOctave = 12;

inline constexpr std::array<float, kRangeExtentSteps> MakeRangeExtents() {
  // 2^(−k/12) for k < 12, then halved exactly per octave.
  constexpr double kOctave[kRangeStepsPerOctave] = {1.0,
                                                    0.94387431268169349,
                                                    0.89089871814033930,
                                                    0.84089641525371454,
                                                    0.79370052598409974,
                                                    0.74915353843834074,
                                                    0.70710678118654752,
                                                    0.66741992708501718,
                                                    0.62996052494743658,
                                                    0.59460355750136054,
                                                    0.56123102415468650,
                                                    0.52973154717964763};
  std::array<float, kRangeExtentSteps> extents{};
  for (int k = 0; k < kRangeExtentSteps; ++k) {
    double e = kOctave[k % kRangeStepsPerOctave];
    for (int h = 0; h < k / kRangeStepsPerOctave; ++h) e *= 0.5;
    extents[k] = static_cast<float>(e);
  }
  return extents;
}
inline constexpr std::array<float, kRangeExtentSteps> kRangeExtents = MakeRangeExtents();

// A drifting range's slope per component: its low end moves by the byte
// (signed) times kSlopeStep of the clip range per sample, up to ±127 steps
// (±half the clip range over a segment of 16 samples). Two steps of the
// range's low end per segment: one fitted fewer segments (CMU 01_01 1.5%
// larger), four measured the same as two.
inline constexpr float kSlopeStep = kInverseRangeLowMax / 8;
inline constexpr int kSlopeMax = 127;

// Slope `c` in steps of kSlopeStep.
inline int SlopeSteps(const uint8_t* slope, int c) { return static_cast<int8_t>(slope[c]); }

inline uint32_t RangeField(const uint8_t* range, int c) {
  return static_cast<uint32_t>(range[2 * c]) | static_cast<uint32_t>(range[2 * c + 1]) << 8;
}
inline uint32_t RangeLow(const uint8_t* range, int c) { return RangeField(range, c) & kRangeLowMax; }
inline float RangeExtent(const uint8_t* range, int c) { return kRangeExtents[RangeField(range, c) >> kRangeLowBits]; }
inline void SetRange(uint8_t* range, int c, uint32_t low, uint32_t extent_step) {
  const uint32_t field = low | extent_step << kRangeLowBits;
  range[2 * c] = static_cast<uint8_t>(field), range[2 * c + 1] = static_cast<uint8_t>(field >> 8);
}

struct TrackCode {
  uint8_t bits = 0;
  uint8_t stride_log = 0;
  bool ranged = false;
  bool sloped = false;  // a drifting segment range (ranged, every frame kept)
};

inline constexpr uint8_t EncodeTrackCode(int bits, int stride_log, bool ranged) {
  return static_cast<uint8_t>(((bits - kMinBits) * kStrideLogs + stride_log) * 2 + (ranged ? 1 : 0));
}
// Drifting ranges keep every frame: one code per bit rate, after the others.
inline constexpr int kFirstSlopedCode = kRateCount * kStrideLogs * 2;
static_assert(kFirstSlopedCode + kRateCount <= 256);
inline constexpr uint8_t EncodeSlopedCode(int bits) { return static_cast<uint8_t>(kFirstSlopedCode + bits - kMinBits); }

inline constexpr std::array<TrackCode, 256> MakeCodes() {
  std::array<TrackCode, 256> codes{};
  for (int bits = kMinBits; bits <= kMaxBits; ++bits) {
    for (int s = 0; s < kStrideLogs; ++s)
      for (int r = 0; r < 2; ++r)
        codes[EncodeTrackCode(bits, s, r == 1)] = {static_cast<uint8_t>(bits), static_cast<uint8_t>(s), r == 1, false};
    codes[EncodeSlopedCode(bits)] = {static_cast<uint8_t>(bits), 0, true, true};
  }
  return codes;
}
inline constexpr std::array<TrackCode, 256> kCodes = MakeCodes();

// A sample's bits per component. The code's bits go to the component with
// the widest range (clip extent × segment extent); a narrower one gets a bit
// less per halving of its range, so every component is quantized with about
// the same step (ACL gives all three the same bits). Decided from what the
// segment stores, so the decoder finds the same.
struct SampleLayout {
  uint8_t bits[3];
  uint8_t total;
};

inline int FloatExponent(float x) {
  uint32_t u;
  std::memcpy(&u, &x, sizeof u);
  return static_cast<int>((u >> 23) & 0xffu);
}

// Writes the per-component bits to `out` (3) and returns their sum: in
// place, so the sampling job's cursors need no copy.
inline uint8_t FillLayout(int bits, const float* clip_extent, const uint8_t* segment_range, uint8_t* out) {
  int exponent[3], widest = 0;
  for (int c = 0; c < 3; ++c) {
    const float extent = clip_extent[c] * (segment_range ? RangeExtent(segment_range, c) : 1.f);
    exponent[c] = FloatExponent(extent);
    widest = exponent[c] > widest ? exponent[c] : widest;
  }
  int total = 0;
  for (int c = 0; c < 3; ++c) {
    const int b = bits - (widest - exponent[c]);
    out[c] = static_cast<uint8_t>(b < 1 ? 1 : b);
    total += out[c];
  }
  return static_cast<uint8_t>(total);
}

inline SampleLayout MakeLayout(int bits, const float* clip_extent, const uint8_t* segment_range) {
  SampleLayout layout;
  layout.total = FillLayout(bits, clip_extent, segment_range, layout.bits);
  return layout;
}

// Samples one track stores in a segment of `intervals` frames; `shares_end`
// when the segment's last frame is the next segment's first.
inline size_t StoredSamples(int stride_log, size_t intervals, bool shares_end) {
  return (intervals >> stride_log) + (shares_end ? 0 : 1);
}

// Bits one track takes in a segment of `intervals` frames.
inline size_t TrackBits(const SampleLayout& layout, int stride_log, size_t intervals, bool shares_end) {
  return static_cast<size_t>(layout.total) * StoredSamples(stride_log, intervals, shares_end);
}

// The `bits`-bit integer at bit `offset` (little-endian, LSB first).
inline uint32_t ReadBits(const uint8_t* data, size_t offset, int bits) {
  uint64_t word;
  std::memcpy(&word, data + (offset >> 3), sizeof word);
  return static_cast<uint32_t>((word >> (offset & 7)) & ((uint64_t{1} << bits) - 1));
}

// Values written one after another from bit `offset` (little-endian, LSB
// first, ORed in: the data starts zeroed), whole bytes as they fill.
class BitWriter {
 public:
  BitWriter(uint8_t* data, size_t offset) : at_(data + (offset >> 3)), used_(static_cast<int>(offset & 7)) {}
  void Put(int bits, uint32_t value) {
    pending_ |= static_cast<uint64_t>(value) << used_;
    for (used_ += bits; used_ >= 8; used_ -= 8, pending_ >>= 8) *at_++ |= static_cast<uint8_t>(pending_);
  }
  ~BitWriter() {
    if (used_ > 0) *at_ |= static_cast<uint8_t>(pending_);
  }

 private:
  uint8_t* at_;
  int used_;
  uint64_t pending_ = 0;
};

// Sample i's value = (offset + scale · q) + i · slope per component: the
// clip range [min, min + extent] and, when ranged, the segment range inside
// it (RangeLow, RangeExtent), drifting by `slope` a sample (0 unless sloped).
struct Dequantizer {
  float offset[3], scale[3], slope[3];
};

inline constexpr std::array<float, kMaxBits + 1> MakeInverseMax() {
  std::array<float, kMaxBits + 1> inv{};
  for (int b = 1; b <= kMaxBits; ++b) inv[b] = 1.f / static_cast<float>((1u << b) - 1);
  return inv;
}
inline constexpr std::array<float, kMaxBits + 1> kInverseMax = MakeInverseMax();

// Writes offset, scale and slope per component (3 each) for `bits` per
// component; `segment_slope` null when the range does not drift.
inline void FillDequantizer(const float* clip_min, const float* clip_extent, const uint8_t* segment_range,
                            const uint8_t* segment_slope, const uint8_t* bits, float* offset, float* scale,
                            float* slope) {
  for (int c = 0; c < 3; ++c) {
    float lo = 0.f, ext = 1.f, drift = 0.f;
    if (segment_range) {
      lo = static_cast<float>(RangeLow(segment_range, c)) * kInverseRangeLowMax;
      ext = RangeExtent(segment_range, c);
    }
    if (segment_slope) drift = static_cast<float>(SlopeSteps(segment_slope, c)) * kSlopeStep;
    offset[c] = clip_min[c] + clip_extent[c] * lo;
    scale[c] = clip_extent[c] * ext * kInverseMax[bits[c]];
    slope[c] = clip_extent[c] * drift;
  }
}

inline Dequantizer MakeDequantizer(const float* clip_min, const float* clip_extent, const uint8_t* segment_range,
                                   const uint8_t* segment_slope, const SampleLayout& layout) {
  Dequantizer d;
  FillDequantizer(clip_min, clip_extent, segment_range, segment_slope, layout.bits, d.offset, d.scale, d.slope);
  return d;
}

// Sample `i`'s three components.
inline void ReadSample(const uint8_t* data, size_t track_bit, const SampleLayout& layout, size_t i,
                       const Dequantizer& d, float* v) {
  size_t at = track_bit + i * layout.total;
  for (int c = 0; c < 3; ++c) {
    v[c] = (d.offset[c] + d.scale[c] * static_cast<float>(ReadBits(data, at, layout.bits[c]))) +
           static_cast<float>(i) * d.slope[c];
    at += layout.bits[c];
  }
}

// √x without libm's errno path (x ≥ 0 here).
inline float Sqrt(float x) {
#if defined(__SSE__)
  return _mm_cvtss_f32(_mm_sqrt_ss(_mm_set_ss(x)));
#else
  return __builtin_sqrtf(x);
#endif
}

inline constexpr float kInverseStride[kStrideLogs] = {1.f, 0.5f, 0.25f, 0.125f, 0.0625f};

// A rotation (x y z w) from its three kept components, in order, and the
// index of the dropped one (kept ≥ 0, so rebuilt as the square root).
inline void ExpandRotation(const float* kept, int dropped, float* q) {
  const float w2 = 1.f - kept[0] * kept[0] - kept[1] * kept[1] - kept[2] * kept[2];
  const float rebuilt = Sqrt(w2 > 0.f ? w2 : 0.f);
  if (dropped == 3) {  // the usual case: w
    q[0] = kept[0], q[1] = kept[1], q[2] = kept[2], q[3] = rebuilt;
    return;
  }
  for (int c = 0, k = 0; c < 4; ++c) q[c] = c == dropped ? rebuilt : kept[k++];
}

// The three kept components of rotation `q` (x y z w) when `dropped` is
// rebuilt: the sign that makes the dropped one ≥ 0 (q and −q are one
// rotation). Undoes ExpandRotation exactly when `dropped` is the same.
inline void ReduceRotation(const float* q, int dropped, float* kept) {
  const float sign = q[dropped] < 0.f ? -1.f : 1.f;
  for (int c = 0, k = 0; c < 4; ++c)
    if (c != dropped) kept[k++] = sign * q[c];
}

// nlerp of two rotations (x y z w), along the shorter arc.
inline void Nlerp(const float* a, const float* b, float u, float* out) {
  const float d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  const float ub = d < 0.f ? -u : u, ua = 1.f - u;
  float n = 0;
  for (int c = 0; c < 4; ++c) {
    out[c] = ua * a[c] + ub * b[c];
    n += out[c] * out[c];
  }
  const float inv = 1.f / Sqrt(n);
  for (int c = 0; c < 4; ++c) out[c] *= inv;
}

}  // namespace armature::compression_internal
