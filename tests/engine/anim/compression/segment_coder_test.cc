// The segment coder's drifting ranges (packed_track.h): a component that
// moves steadily through a segment is quantized in a narrow band around its
// line, and decodes (as the sampling job reads it) within the target.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "anim/compression/packed_track.h"
#include "anim/compression/segment_coder.h"

namespace armature::compression_internal {
namespace {

constexpr size_t kFrames = kSegmentFrames + 1;
constexpr float kZero[3] = {0.f, 0.f, 0.f}, kOne[3] = {1.f, 1.f, 1.f};

// One translation track over a last segment (its 17 frames all stored), in
// a clip range of [0, 1] per component: `at(f, c)` is the value.
template <class At>
struct Track {
  explicit Track(At at) {
    for (size_t f = 0; f < kFrames; ++f)
      for (int c = 0; c < 3; ++c) raw[f * 4 + c] = normalized[f * 3 + c] = at(static_cast<double>(f), c);
    in.kind = TrackKind::kTranslation;
    in.intervals = kSegmentFrames;
    in.raw = raw;
    in.normalized = normalized;
    in.clip_min = kZero;
    in.clip_extent = kOne;
  }
  std::vector<double> raw = std::vector<double>(kFrames * 4, 0.0), normalized = std::vector<double>(kFrames * 3);
  SegmentTrackInput in;
};

// The largest distance of a frame's decoded value (ReadSample's samples,
// interpolated between strided ones) from its value.
double WorstDecoded(const SegmentTrackInput& in, const SegmentTrackChoice& choice) {
  const TrackCode code = kCodes[choice.code];
  const uint8_t* range = code.ranged ? choice.range : nullptr;
  const SampleLayout layout = MakeLayout(code.bits, in.clip_extent, range);
  const Dequantizer d =
      MakeDequantizer(in.clip_min, in.clip_extent, range, code.sloped ? choice.slope : nullptr, layout);
  std::vector<uint8_t> data(layout.total * kFrames / 8 + 1 + kReadPadding, 0);
  PackSegmentTrack(in, choice, data.data(), 0);
  const size_t stride = size_t{1} << code.stride_log, samples = kSegmentFrames / stride + 1;
  double worst = 0;
  for (size_t f = 0; f < kFrames; ++f) {
    const size_t i = std::min(f / stride, samples - 2);
    const double u = static_cast<double>(f - i * stride) / static_cast<double>(stride);
    float a[3], b[3];
    ReadSample(data.data(), 0, layout, i, d, a);
    ReadSample(data.data(), 0, layout, i + 1, d, b);
    double e2 = 0;
    for (int c = 0; c < 3; ++c) {
      const double v = a[c] + u * (b[c] - a[c]) - in.raw[f * 4 + c];
      e2 += v * v;
    }
    worst = std::max(worst, std::sqrt(e2));
  }
  return worst;
}

TEST(SegmentCoder, ASteadyDriftIsQuantizedAroundItsLine) {
  // Two components cross much of the clip range; the wobble around the
  // lines is 0.002.
  Track track([](double f, int c) {
    if (c == 0) return 0.1 + 0.4 * f / 16 + 0.002 * std::sin(1.7 * f);
    if (c == 1) return 0.3 + 0.002 * std::cos(2.3 * f);
    return 0.9 - 0.2 * f / 16;
  });
  constexpr double kTarget = 2e-4;
  const std::optional<SegmentTrackChoice> choice = ChooseSegmentTrack(track.in, kTarget);
  ASSERT_TRUE(choice.has_value());
  const TrackCode code = kCodes[choice->code];
  EXPECT_TRUE(code.sloped);
  EXPECT_EQ(code.stride_log, 0);
  // A range over the samples would need 0.4 / (2 · 2e-4): 10 bits and more
  // for the widest component; around the lines the band is about 0.005.
  EXPECT_LE(code.bits, 7);
  EXPECT_EQ(SlopeSteps(choice->slope, 0), static_cast<int>(std::lround(0.4 / 16 / kSlopeStep)));
  EXPECT_LE(WorstDecoded(track.in, *choice), kTarget);
}

TEST(SegmentCoder, ADriftPastTheSlopesReachKeepsARange) {
  // The whole clip range in one segment: 1/16 a sample is past 127 steps.
  Track track([](double f, int c) { return c == 0 ? 0.01 + 0.98 * f / 16 + 0.002 * std::sin(1.7 * f) : 0.5; });
  constexpr double kTarget = 2e-4;
  const std::optional<SegmentTrackChoice> choice = ChooseSegmentTrack(track.in, kTarget);
  ASSERT_TRUE(choice.has_value());
  EXPECT_FALSE(kCodes[choice->code].sloped);
  EXPECT_LE(WorstDecoded(track.in, *choice), kTarget);
}

}  // namespace
}  // namespace armature::compression_internal
