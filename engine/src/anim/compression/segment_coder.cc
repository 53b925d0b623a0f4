#include "anim/compression/segment_coder.h"

#include "anim/compression/clip_reference.h"

#include <algorithm>
#include <cmath>

namespace armature::compression_internal {
namespace {

constexpr size_t kMaxFrames = kSegmentFrames + 1;

// One past the last frame the segment stores: its last frame is the next
// segment's when it shares it.
size_t StoredEnd(const SegmentTrackInput& in) { return in.end ? in.intervals : in.intervals + 1; }

// The shared end sample as the sampling job reads it: reduced to this
// segment's kept components, then rebuilt.
void EndSample(const SegmentTrackInput& in, float* out) {
  if (in.kind != TrackKind::kRotation) {
    std::copy(in.end, in.end + 3, out);
    return;
  }
  float kept[3];
  ReduceRotation(in.end, in.dropped, kept);
  ExpandRotation(kept, in.dropped, out);
}

// The largest extent step (kRangeExtents[k] = 2^(−k/12), falling with k)
// whose extent is at least `needed`: from the logarithm, then checked
// against the table's floats.
uint32_t NarrowestStepReaching(double needed) {
  constexpr int kLast = kRangeExtentSteps - 1;
  if (needed <= kRangeExtents[kLast]) return kLast;
  int k = std::clamp(static_cast<int>(-kRangeStepsPerOctave * std::log2(needed)), 0, kLast);
  while (k < kLast && kRangeExtents[k + 1] >= needed) ++k;
  while (k > 0 && kRangeExtents[k] < needed) --k;
  return static_cast<uint32_t>(k);
}

// Component `c` of a segment range holding [lo, hi]: low end rounded
// down, extent the narrowest step that still reaches `hi`, so every value
// lies inside.
void SetBand(uint8_t* range, int c, double lo, double hi) {
  const uint32_t lo_q = static_cast<uint32_t>(std::clamp(std::floor(lo * kRangeLowMax), 0.0, double{kRangeLowMax}));
  SetRange(range, c, lo_q, NarrowestStepReaching(hi - lo_q / double{kRangeLowMax}));
}

// The segment range over the samples a stride keeps.
void SegmentRange(const SegmentTrackInput& in, int stride_log, uint8_t* range) {
  for (int c = 0; c < 3; ++c) {
    double lo = 1, hi = 0;
    for (size_t f = 0; f < StoredEnd(in); f += size_t{1} << stride_log) {
      lo = std::min(lo, in.normalized[f * 3 + c]);
      hi = std::max(hi, in.normalized[f * 3 + c]);
    }
    SetBand(range, c, lo, hi);
  }
}

// A drifting segment range over every frame the segment stores: per
// component the least-squares slope, in whole kSlopeStep steps, and the
// band of what is left around it. False when a slope is beyond kSlopeMax
// steps, or the band leaves the clip range (its low end is stored unsigned).
bool SlopedRange(const SegmentTrackInput& in, uint8_t* range, uint8_t* slope) {
  const size_t n = StoredEnd(in);
  if (n < 3) return false;
  const double mean_i = static_cast<double>(n - 1) / 2;
  double sii = 0;
  for (size_t i = 0; i < n; ++i) sii += (static_cast<double>(i) - mean_i) * (static_cast<double>(i) - mean_i);
  for (int c = 0; c < 3; ++c) {
    double mean_v = 0, siv = 0;
    for (size_t i = 0; i < n; ++i) mean_v += in.normalized[i * 3 + c];
    mean_v /= static_cast<double>(n);
    for (size_t i = 0; i < n; ++i) siv += (static_cast<double>(i) - mean_i) * (in.normalized[i * 3 + c] - mean_v);
    const double steps = std::round(siv / sii / double{kSlopeStep});
    if (!(std::abs(steps) <= kSlopeMax)) return false;
    const double drift = steps * double{kSlopeStep};
    double lo = 2, hi = -1;
    for (size_t i = 0; i < n; ++i) {
      const double r = in.normalized[i * 3 + c] - static_cast<double>(i) * drift;
      lo = std::min(lo, r), hi = std::max(hi, r);
    }
    if (lo < 0 || hi > 1) return false;
    SetBand(range, c, lo, hi);
    slope[c] = static_cast<uint8_t>(static_cast<int8_t>(steps));
  }
  return true;
}

// Where a choice quantizes: the clip range (no segment range), a segment
// range, or a drifting one (a range and its slope).
struct Band {
  const uint8_t* range = nullptr;
  const uint8_t* slope = nullptr;
};

Band BandOf(const SegmentTrackChoice& choice) {
  const TrackCode code = kCodes[choice.code];
  return {code.ranged ? choice.range : nullptr, code.sloped ? choice.slope : nullptr};
}

// Normalized values to `bits`-bit integers per component, in the segment
// range when there is one; its ends and the integer ranges worked out once
// per choice, not per value (the same arithmetic, so the same integers).
struct Quantizer {
  Quantizer(Band band, const SampleLayout& layout) : ranged(band.range != nullptr) {
    for (int c = 0; c < 3; ++c) {
      if (ranged) lo[c] = RangeLow(band.range, c) / double{kRangeLowMax}, extent[c] = RangeExtent(band.range, c);
      if (band.slope) drift[c] = SlopeSteps(band.slope, c) * double{kSlopeStep};
      max_q[c] = static_cast<double>((1u << layout.bits[c]) - 1);
    }
  }
  // Sample `i`'s component `c`.
  uint32_t operator()(double normalized, int c, size_t i) const {
    double v = normalized;
    if (ranged) v = (v - lo[c] - static_cast<double>(i) * drift[c]) / extent[c];
    return static_cast<uint32_t>(std::clamp(v * max_q[c] + 0.5, 0.0, max_q[c]));  // rounded: v ≥ 0
  }
  bool ranged;
  double lo[3] = {}, extent[3] = {}, drift[3] = {}, max_q[3];
};

// A choice's decoded samples (as the sampling job reads them), one at a
// time: ChoiceError stops at the first frame above its target, and a choice
// that fails usually fails early, so decoding all of them first was most
// of its cost.
class SampleDecoder {
 public:
  SampleDecoder(const SegmentTrackInput& in, int bits, int stride_log, Band band)
      : in_(in),
        stride_log_(stride_log),
        layout_(MakeLayout(bits, in.clip_extent, band.range)),
        dequantize_(MakeDequantizer(in.clip_min, in.clip_extent, band.range, band.slope, layout_)),
        quantize_(band, layout_),
        stored_((StoredEnd(in) - 1) / (size_t{1} << stride_log) + 1) {}

  // Samples kept: the stored ones, then the shared end (SharedEnd's).
  size_t Stored() const { return stored_; }
  size_t Count() const { return stored_ + (in_.end ? 1 : 0); }

  void Decode(size_t i, float* out) const {
    const size_t f = i << stride_log_;
    float kept[3];
    for (int c = 0; c < 3; ++c)  // ReadSample's arithmetic
      kept[c] = (dequantize_.offset[c] +
                 dequantize_.scale[c] * static_cast<float>(quantize_(in_.normalized[f * 3 + c], c, i))) +
                static_cast<float>(i) * dequantize_.slope[c];
    if (in_.kind == TrackKind::kRotation)
      ExpandRotation(kept, in_.dropped, out);
    else
      std::copy(kept, kept + 3, out);
  }

 private:
  const SegmentTrackInput& in_;
  int stride_log_;
  SampleLayout layout_;
  Dequantizer dequantize_;
  Quantizer quantize_;
  size_t stored_;
};

// The squared value error of decoded `r` (interpolated) against the stored `raw`.
double FrameError2(const SegmentTrackInput& in, const double* raw, const float* a, const float* b, float u) {
  if (in.kind == TrackKind::kRotation) {
    float r[4];
    Nlerp(a, b, u, r);
    return RotationChordSquared(raw, r);
  }
  double e2 = 0;
  for (int c = 0; c < 3; ++c) {
    const double v = a[c] + u * (b[c] - a[c]);
    e2 += (v - raw[c]) * (v - raw[c]);
  }
  return e2;
}

// The shared end as every choice in the segment decodes it, and its own
// error at the segment's last frame: the same for every choice, so worked
// out once per track and segment, not per ChoiceError.
struct SharedEnd {
  float sample[4] = {};
  double error = 0;
};

SharedEnd MakeSharedEnd(const SegmentTrackInput& in) {
  SharedEnd end;
  if (!in.end) return end;
  EndSample(in, end.sample);
  end.error = std::sqrt(FrameError2(in, &in.raw[in.intervals * 4], end.sample, end.sample, 0.f));
  return end;
}

// The largest displacement over the segment's frames, or early once above
// `target`. Compared squared, per unit of lever. A shared end (the next
// segment's first sample) has its own error, which no choice here changes:
// the last interval is allowed the blend of the target and that error, and
// the result is scaled so that ≤ target means every frame is allowed.
double ChoiceError(const SegmentTrackInput& in, const SharedEnd& end, int bits, int stride_log, Band band,
                   double target) {
  float samples[kMaxFrames][4];
  const SampleDecoder decoder(in, bits, stride_log, band);
  const size_t count = decoder.Count();
  const float inv_stride = kInverseStride[stride_log];
  const double limit = target / in.lever;
  if (in.end) std::copy(end.sample, end.sample + 4, samples[count - 1]);
  size_t decoded = 0;  // samples[0, decoded) are decoded (and the end, copied above)
  double worst = 0;    // the largest squared error over its allowed square
  for (size_t f = 0; f <= in.intervals; ++f) {
    const size_t i = std::min(f >> stride_log, count - 2);
    for (; decoded <= i + 1 && decoded < decoder.Stored(); ++decoded) decoder.Decode(decoded, samples[decoded]);
    const float u = static_cast<float>(f - (i << stride_log)) * inv_stride;
    const double e2 = FrameError2(in, &in.raw[f * 4], samples[i], samples[i + 1], u);
    double allowed = limit;
    if (in.end && i + 2 == count) allowed = std::max(limit, (1 - u) * limit + u * end.error);
    worst = std::max(worst, e2 / (allowed * allowed));
    if (worst > 1) break;
  }
  return std::sqrt(worst) * target;
}

// The fewest bits in [lo, kMaxBits] meeting `target` (errors shrink with
// bits), or 0. A hint (the neighbouring segment's bits) starts a walk that
// usually ends in two or three tries; without one, a binary search.
int FewestBits(const SegmentTrackInput& in, const SharedEnd& end, int stride_log, Band band, double target, int lo) {
  auto meets = [&](int bits) { return ChoiceError(in, end, bits, stride_log, band, target) <= target; };
  int hi = kMaxBits;
  if (in.hint_stride_log == stride_log && in.hint_bits >= lo && in.hint_bits <= kMaxBits) {
    int bits = in.hint_bits;
    if (meets(bits)) {
      while (bits > lo && meets(bits - 1)) --bits;
      return bits;
    }
    if (!meets(hi)) return 0;
    while (++bits < hi)
      if (meets(bits)) return bits;
    return hi;
  }
  if (!meets(hi)) return 0;
  while (lo < hi) {
    const int mid = (lo + hi) / 2;
    if (meets(mid))
      hi = mid;
    else
      lo = mid + 1;
  }
  return hi;
}

// A drifting range (every frame kept), as `best` when it is cheaper.
void TryDrifting(const SegmentTrackInput& in, const SharedEnd& end, double target,
                 std::optional<SegmentTrackChoice>& best) {
  SegmentTrackChoice sloped;
  if (!SlopedRange(in, sloped.range, sloped.slope)) return;
  const int bits = FewestBits(in, end, 0, {sloped.range, sloped.slope}, target, kMinBits);
  if (bits == 0) return;
  sloped.code = EncodeSlopedCode(bits);
  sloped.bits = TrackBits(MakeLayout(bits, in.clip_extent, sloped.range), 0, in.intervals, in.end != nullptr) +
                8 * TailBytes(sloped);
  if (!best || sloped.bits < best->bits) best = sloped;
}

}  // namespace

std::optional<SegmentTrackChoice> ChooseSegmentTrack(const SegmentTrackInput& in, double target) {
  std::optional<SegmentTrackChoice> best;
  const SharedEnd end = MakeSharedEnd(in);
  for (int s = kStrideLogs - 1; s >= 0; --s) {
    const size_t stride = size_t{1} << s;
    if (in.intervals % stride != 0) continue;
    const size_t samples = StoredSamples(s, in.intervals, in.end != nullptr);
    if (best && (kMinBits + 2) * samples >= best->bits) continue;  // cannot be cheaper
    SegmentTrackChoice ranged;
    SegmentRange(in, s, ranged.range);
    const int ranged_bits = FewestBits(in, end, s, {ranged.range}, target, kMinBits);
    if (ranged_bits == 0) continue;
    ranged.code = EncodeTrackCode(ranged_bits, s, true);
    ranged.bits = TrackBits(MakeLayout(ranged_bits, in.clip_extent, ranged.range), s, in.intervals, in.end != nullptr) +
                  8 * kRangeBytes;
    if (!best || ranged.bits < best->bits) best = ranged;
    // Without a segment range: more bits per sample, no range bytes.
    for (int bits = ranged_bits; bits <= std::min(kMaxBits, ranged_bits + 4); ++bits) {
      SegmentTrackChoice plain;
      plain.code = EncodeTrackCode(bits, s, false);
      plain.bits = TrackBits(MakeLayout(bits, in.clip_extent, nullptr), s, in.intervals, in.end != nullptr);
      if (plain.bits >= best->bits) break;
      if (ChoiceError(in, end, bits, s, {}, target) <= target) {
        best = plain;
        break;
      }
    }
    if (s == 0) TryDrifting(in, end, target, best);
  }
  return best;
}

void DecodeFirstSample(const SegmentTrackInput& in, const SegmentTrackChoice& choice, float* out) {
  const TrackCode code = kCodes[choice.code];
  float sample[4] = {};  // a vector's fourth stays 0
  SampleDecoder(in, code.bits, code.stride_log, BandOf(choice)).Decode(0, sample);
  std::copy(sample, sample + 4, out);
}

void PackSegmentTrack(const SegmentTrackInput& in, const SegmentTrackChoice& choice, uint8_t* data, size_t offset) {
  const TrackCode code = kCodes[choice.code];
  const Band band = BandOf(choice);
  const SampleLayout layout = MakeLayout(code.bits, in.clip_extent, band.range);
  const Quantizer quantize(band, layout);
  BitWriter writer(data, offset);
  for (size_t f = 0, i = 0; f < StoredEnd(in); f += size_t{1} << code.stride_log, ++i)
    for (int c = 0; c < 3; ++c) writer.Put(layout.bits[c], quantize(in.normalized[f * 3 + c], c, i));
}

}  // namespace armature::compression_internal
