#include "anim/compression/track_state.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace armature::compression_internal {
namespace {

// Below this, the best component over the whole clip comes too near 0 to be
// rebuilt from the others: each segment then picks its own.
constexpr double kSafeDropped = 0.3;

// What is quantized: a rotation's three kept components, with the dropped
// one ≥ 0, or a vector.
void Components(const TrackValues& t, int dropped, size_t f, double* v) {
  const double* raw = &t.raw[f * 4];
  if (t.kind != TrackKind::kRotation) {
    std::copy(raw, raw + 3, v);
    return;
  }
  const double sign = raw[dropped] < 0 ? -1 : 1;
  for (int c = 0, k = 0; c < 4; ++c)
    if (c != dropped) v[k++] = sign * raw[c];
}

// The rotation component farthest from 0 over frames [begin, end]; w unless
// another is clearly safer. `least` receives its smallest magnitude.
int FarthestFromZero(const TrackValues& t, size_t begin, size_t end, double& least) {
  double smallest[4] = {1, 1, 1, 1};
  for (size_t f = begin; f <= end; ++f)
    for (int c = 0; c < 4; ++c) smallest[c] = std::min(smallest[c], std::abs(t.raw[f * 4 + c]));
  int best = 3;
  for (int c = 0; c < 3; ++c)
    if (smallest[c] > smallest[best] + 1e-3) best = c;
  least = smallest[best];
  return best;
}

void Segment(const FrameGrid& frames, size_t segment, size_t& start, size_t& intervals) {
  start = segment * kSegmentFrames;
  intervals = std::min(kSegmentFrames, frames.count - 1 - start);
}

}  // namespace

TrackState MakeTrackState(const TrackValues& t, const FrameGrid& frames, double first_target) {
  TrackState s;
  s.values = &t;
  const size_t segments = SegmentCount(frames.count), count = t.raw.size() / 4;
  s.track.joint = t.joint;
  s.track.kind = t.kind;
  s.dropped.assign(segments, 3);
  if (t.kind == TrackKind::kRotation) {
    double least = 0;
    s.track.dropped = static_cast<uint8_t>(FarthestFromZero(t, 0, count - 1, least));
    if (least < kSafeDropped) s.track.dropped = kDroppedPerSegment;
  }
  for (size_t seg = 0; seg < segments; ++seg) {
    size_t start, intervals;
    Segment(frames, seg, start, intervals);
    double least = 0;
    s.dropped[seg] = s.track.dropped == kDroppedPerSegment
                         ? static_cast<uint8_t>(FarthestFromZero(t, start, start + intervals, least))
                         : s.track.dropped;
  }
  // The clip range: the components' bounds over every frame, in float,
  // rounded outwards; [-1, 1] when each segment drops its own component.
  double lo[3], hi[3], v[3];
  std::fill(lo, lo + 3, std::numeric_limits<double>::infinity());
  std::fill(hi, hi + 3, -std::numeric_limits<double>::infinity());
  if (s.track.dropped == kDroppedPerSegment) {
    std::fill(lo, lo + 3, -1.0);
    std::fill(hi, hi + 3, 1.0);
  } else {
    for (size_t f = 0; f < count; ++f) {
      Components(t, s.track.dropped, f, v);
      for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], v[c]), hi[c] = std::max(hi[c], v[c]);
    }
  }
  for (int c = 0; c < 3; ++c) {
    float min = static_cast<float>(lo[c]);
    if (min > lo[c]) min = std::nextafter(min, -std::numeric_limits<float>::infinity());
    float extent = static_cast<float>(hi[c] - min);
    if (min + extent < hi[c]) extent = std::nextafter(extent, std::numeric_limits<float>::infinity());
    s.track.min[c] = min;
    s.track.extent[c] = extent;
  }
  s.target.assign(segments, first_target);
  s.choice.assign(segments, {});
  s.chosen_at.assign(segments, 0.0);
  s.end.assign(segments, {0, 0, 0, 1});
  return s;
}

SegmentTrackInput SegmentInput(const TrackState& s, const FrameGrid& frames, size_t segment, SegmentValues& values) {
  size_t start, intervals;
  Segment(frames, segment, start, intervals);
  double v[3];
  for (size_t f = 0; f <= intervals; ++f) {
    Components(*s.values, s.dropped[segment], start + f, v);
    for (int c = 0; c < 3; ++c)
      values.normalized[f * 3 + c] =
          s.track.extent[c] > 0 ? std::clamp((v[c] - s.track.min[c]) / s.track.extent[c], 0.0, 1.0) : 0.0;
  }
  SegmentTrackInput in;
  in.kind = s.track.kind;
  in.dropped = s.dropped[segment];
  in.intervals = intervals;
  in.raw = std::span<const double>(s.values->raw).subspan(start * 4, (intervals + 1) * 4);
  in.normalized = std::span<const double>(values.normalized).first((intervals + 1) * 3);
  in.clip_min = s.track.min;
  in.clip_extent = s.track.extent;
  in.lever = s.values->segment_lever[segment];
  if (segment + 1 < s.choice.size()) in.end = s.end[segment].data();
  return in;
}

void UpdateEnd(TrackState& s, const FrameGrid& frames, size_t segment) {
  if (segment + 1 < s.choice.size()) {
    SegmentValues values;
    DecodeFirstSample(SegmentInput(s, frames, segment + 1, values), s.choice[segment + 1], s.end[segment].data());
  }
}

}  // namespace armature::compression_internal
