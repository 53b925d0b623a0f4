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

// The segment range over the samples a stride keeps: low end rounded
// down, extent the narrowest step that still reaches the highest sample,
// so every sample lies inside.
void SegmentRange(const SegmentTrackInput& in, int stride_log, uint8_t* range) {
  for (int c = 0; c < 3; ++c) {
    double lo = 1, hi = 0;
    for (size_t f = 0; f < StoredEnd(in); f += size_t{1} << stride_log) {
      lo = std::min(lo, in.normalized[f * 3 + c]);
      hi = std::max(hi, in.normalized[f * 3 + c]);
    }
    const uint32_t lo_q = static_cast<uint32_t>(std::clamp(std::floor(lo * kRangeLowMax), 0.0, double{kRangeLowMax}));
    const double needed = hi - lo_q / double{kRangeLowMax};
    SetRange(range, c, lo_q, NarrowestStepReaching(needed));
  }
}

// Normalized values to `bits`-bit integers per component, in the segment
// range when there is one; its ends and the integer ranges worked out once
// per choice, not per value (the same arithmetic, so the same integers).
struct Quantizer {
  Quantizer(const uint8_t* range, const SampleLayout& layout) : ranged(range != nullptr) {
    for (int c = 0; c < 3; ++c) {
      if (ranged) lo[c] = RangeLow(range, c) / double{kRangeLowMax}, extent[c] = RangeExtent(range, c);
      max_q[c] = static_cast<double>((1u << layout.bits[c]) - 1);
    }
  }
  uint32_t operator()(double normalized, int c) const {
    double v = normalized;
    if (ranged) v = (v - lo[c]) / extent[c];
    return static_cast<uint32_t>(std::clamp(v * max_q[c] + 0.5, 0.0, max_q[c]));  // rounded: v ≥ 0
  }
  bool ranged;
  double lo[3] = {}, extent[3] = {}, max_q[3];
};

// A choice's decoded samples (as the sampling job reads them), one at a
// time: ChoiceError stops at the first frame above its target, and a choice
// that fails usually fails early, so decoding all of them first was most
// of its cost.
class SampleDecoder {
 public:
  SampleDecoder(const SegmentTrackInput& in, int bits, int stride_log, const uint8_t* range)
      : in_(in),
        stride_log_(stride_log),
        layout_(MakeLayout(bits, in.clip_extent, range)),
        dequantize_(MakeDequantizer(in.clip_min, in.clip_extent, range, layout_)),
        quantize_(range, layout_),
        stored_((StoredEnd(in) - 1) / (size_t{1} << stride_log) + 1) {}

  // Samples kept: the stored ones, then the shared end (SharedEnd's).
  size_t Stored() const { return stored_; }
  size_t Count() const { return stored_ + (in_.end ? 1 : 0); }

  void Decode(size_t i, float* out) const {
    const size_t f = i << stride_log_;
    float kept[3];
    for (int c = 0; c < 3; ++c)
      kept[c] =
          dequantize_.offset[c] + dequantize_.scale[c] * static_cast<float>(quantize_(in_.normalized[f * 3 + c], c));
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
double ChoiceError(const SegmentTrackInput& in, const SharedEnd& end, int bits, int stride_log, const uint8_t* range,
                   double target) {
  float samples[kMaxFrames][4];
  const SampleDecoder decoder(in, bits, stride_log, range);
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
int FewestBits(const SegmentTrackInput& in, const SharedEnd& end, int stride_log, const uint8_t* range, double target,
               int lo) {
  auto meets = [&](int bits) { return ChoiceError(in, end, bits, stride_log, range, target) <= target; };
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
    const int ranged_bits = FewestBits(in, end, s, ranged.range, target, kMinBits);
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
      if (ChoiceError(in, end, bits, s, nullptr, target) <= target) {
        best = plain;
        break;
      }
    }
  }
  return best;
}

void DecodeFirstSample(const SegmentTrackInput& in, const SegmentTrackChoice& choice, float* out) {
  const TrackCode code = kCodes[choice.code];
  float sample[4] = {};  // a vector's fourth stays 0
  SampleDecoder(in, code.bits, code.stride_log, code.ranged ? choice.range : nullptr).Decode(0, sample);
  std::copy(sample, sample + 4, out);
}

void PackSegmentTrack(const SegmentTrackInput& in, const SegmentTrackChoice& choice, uint8_t* data, size_t offset) {
  const TrackCode code = kCodes[choice.code];
  const uint8_t* range = code.ranged ? choice.range : nullptr;
  const SampleLayout layout = MakeLayout(code.bits, in.clip_extent, range);
  const Quantizer quantize(range, layout);
  BitWriter writer(data, offset);
  for (size_t f = 0; f < StoredEnd(in); f += size_t{1} << code.stride_log)
    for (int c = 0; c < 3; ++c) writer.Put(layout.bits[c], quantize(in.normalized[f * 3 + c], c));
}

}  // namespace armature::compression_internal
