#include "armature/engine/anim/compression/compressed_weights.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "anim/compression/packed_track.h"

namespace armature {
namespace {

using compression_internal::BitWriter;
using compression_internal::kReadPadding;
using compression_internal::ReadBits;

constexpr int kMaxWeightBits = 24;
constexpr int kWeightStrideLogs = 7;  // strides 1 to 64 frames

// Samples a target keeps at `stride_log` over `frames` frames: every
// stride-th frame and the last.
size_t SampleCount(size_t frames, int stride_log) {
  const size_t last = frames - 1;
  return (last >> stride_log) + 1 + ((last & ((size_t{1} << stride_log) - 1)) ? 1 : 0);
}

float Dequantize(const CompressedWeights::Target& t, uint32_t q) { return t.min + t.scale * static_cast<float>(q); }

float SampleAt(const CompressedWeights& w, const CompressedWeights::Target& t, size_t i) {
  return t.bits == 0 ? t.min : Dequantize(t, ReadBits(w.data.data(), t.bit_offset + i * t.bits, t.bits));
}

// The weight at frame position `x` in [0, frames − 1], from `sample(i)`.
template <typename Sample>
double Interpolate(size_t frames, int stride_log, double x, const Sample& sample) {
  const size_t last = frames - 1, at = std::min(static_cast<size_t>(x), last);
  const size_t i = at >> stride_log, a = i << stride_log, b = std::min(a + (size_t{1} << stride_log), last);
  const double va = sample(i);
  if (b == a) return va;
  const double u = (x - static_cast<double>(a)) / static_cast<double>(b - a);
  return va + u * (static_cast<double>(sample(i + 1)) - va);
}

// The quantized samples of `values` (one per frame) at a stride and bits,
// their dequantizer in `t`; the worst error over every frame comes back.
double TryTarget(std::span<const double> values, int stride_log, int bits, double lo, double hi,
                 CompressedWeights::Target& t, std::vector<uint32_t>& q) {
  const size_t frames = values.size(), count = SampleCount(frames, stride_log);
  q.assign(count, 0);
  t.bits = static_cast<uint8_t>(bits);
  t.stride_log = static_cast<uint8_t>(stride_log);
  if (bits == 0) {
    t.min = static_cast<float>(0.5 * (lo + hi));
    t.scale = 0;
  } else {
    const double max_q = static_cast<double>((1u << bits) - 1);
    t.min = static_cast<float>(lo);
    t.scale = static_cast<float>((hi - static_cast<double>(t.min)) / max_q);
    for (size_t i = 0; i < count; ++i) {
      const double v = values[std::min(i << stride_log, frames - 1)];
      const double exact = t.scale > 0 ? (v - t.min) / t.scale : 0;
      q[i] = static_cast<uint32_t>(std::clamp(std::round(exact), 0.0, max_q));
    }
  }
  double worst = 0;
  for (size_t f = 0; f < frames; ++f) {
    const double v = Interpolate(frames, stride_log, static_cast<double>(f),
                                 [&](size_t i) { return bits == 0 ? t.min : Dequantize(t, q[i]); });
    worst = std::max(worst, std::abs(v - values[f]));
  }
  return worst;
}

}  // namespace

size_t CompressedWeights::ByteSize() const { return mesh.size() + targets.size() * sizeof(Target) + data.size(); }

double WeightBound(const ErrorBound& bound) { return bound.precision / bound.shell_distance; }

std::optional<CompressedWeights> CompressWeights(const WeightsTrack& track, const FrameGrid& frames,
                                                 double weight_bound, double& worst) {
  CompressedWeights out;
  out.mesh = track.mesh;
  out.targets.resize(track.targets);
  worst = 0;
  const size_t n = std::max<size_t>(frames.count, 1);
  std::vector<double> sampled(n * track.targets), values(n);
  for (size_t f = 0; f < n; ++f)
    SampleWeights(track, frames.Time(f), {std::nullopt, WrapMode::kClamp},
                  std::span<double>(sampled.data() + f * track.targets, track.targets));
  std::vector<std::vector<uint32_t>> chosen(track.targets);
  std::vector<uint32_t> q;
  size_t bits_total = 0;
  for (size_t k = 0; k < track.targets; ++k) {
    for (size_t f = 0; f < n; ++f) values[f] = sampled[f * track.targets + k];
    const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    size_t best = std::numeric_limits<size_t>::max();
    double best_error = 0;
    CompressedWeights::Target t;
    // The cheapest stride and bits meeting the bound; errors shrink with bits.
    for (int s = 0; s < kWeightStrideLogs && (s == 0 || (size_t{1} << s) < n); ++s) {
      for (int bits = 0; bits <= kMaxWeightBits; ++bits) {
        const size_t cost = static_cast<size_t>(bits) * SampleCount(n, s);
        if (cost >= best) break;
        const double e = TryTarget(values, s, bits, *lo, *hi, t, q);
        if (e > weight_bound) continue;
        best = cost, best_error = e;
        out.targets[k] = t;
        chosen[k] = q;
        break;
      }
    }
    if (best == std::numeric_limits<size_t>::max()) return std::nullopt;
    out.targets[k].bit_offset = static_cast<uint32_t>(bits_total);
    bits_total += best;
    worst = std::max(worst, best_error);
  }
  out.data.assign((bits_total + 7) / 8 + kReadPadding, 0);
  for (size_t k = 0; k < track.targets; ++k) {
    const CompressedWeights::Target& t = out.targets[k];
    BitWriter writer(out.data.data(), t.bit_offset);
    for (size_t i = 0; t.bits > 0 && i < chosen[k].size(); ++i) writer.Put(t.bits, chosen[k][i]);
  }
  return out;
}

void SampleCompressedWeights(const CompressedWeights& weights, const FrameGrid& frames, double time,
                             const std::optional<Interpolation>& interpolation, std::span<double> out) {
  const size_t n = std::max<size_t>(frames.count, 1);
  double x = frames.frame_time > 0 ? std::clamp(time / frames.frame_time, 0.0, static_cast<double>(n - 1)) : 0;
  if (interpolation == Interpolation::kStep) x = std::floor(x + 1e-9 * std::max(1.0, x));
  for (size_t k = 0; k < weights.targets.size() && k < out.size(); ++k) {
    const CompressedWeights::Target& t = weights.targets[k];
    out[k] = Interpolate(n, t.stride_log, x, [&](size_t i) { return SampleAt(weights, t, i); });
  }
}

WeightsTrack WeightsKeysOf(const CompressedWeights& weights, const FrameGrid& frames, double duration) {
  WeightsTrack track;
  track.mesh = weights.mesh;
  track.targets = weights.targets.size();
  const size_t n = std::max<size_t>(frames.count, 1);
  track.times.resize(n);
  track.values.resize(n * track.targets);
  for (size_t f = 0; f < n; ++f) {
    track.times[f] = f + 1 == n ? duration : frames.Time(f);
    SampleCompressedWeights(weights, frames, frames.Time(f), std::nullopt,
                            std::span<double>(track.values.data() + f * track.targets, track.targets));
  }
  return track;
}

}  // namespace armature
