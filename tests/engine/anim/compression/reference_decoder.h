// A plain decoder of the packed runtime form (packed_track.h), written
// straight from the format with its own primitives (layout, dequantizer,
// ReadBits), one track and one component at a time, and the nlerp and
// double Newton step the sampling job documents, in the same order of
// operations. The sampling job's fast paths must give its values bit for bit.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "anim/compression/packed_track.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/math/transform.h"

namespace armature::test_util {

class ReferenceDecoder {
 public:
  explicit ReferenceDecoder(const CompressedClip& clip) : clip_(clip) {}

  // The pose at `t` (clamped to the clip; LINEAR), every joint.
  std::vector<Trs> Pose(double t) const {
    std::vector<Trs> pose(clip_.skeleton->rest.begin(), clip_.skeleton->rest.end());
    for (const ConstantTrack& c : clip_.constants) Store(c.kind, c.value, pose[c.joint]);
    if (clip_.animated.empty()) return pose;
    const Position at = Locate(t);
    const std::vector<Cursor> here = Header(at.segment);
    std::vector<Cursor> next;
    if (at.shares_end) next = Header(at.segment + 1);
    for (size_t k = 0; k < clip_.animated.size(); ++k) {
      const AnimatedTrack& track = clip_.animated[k];
      const Cursor& c = here[k];
      const size_t samples = at.intervals >> c.stride_log;
      const size_t i = std::min(static_cast<size_t>(at.q) >> c.stride_log, samples - 1);
      const float u =
          (at.q - static_cast<float>(i << c.stride_log)) * compression_internal::kInverseStride[c.stride_log];
      float a[3], b[3];
      Read(clip_.data.data() + clip_.segment_offsets[at.segment], c, i, a);
      if (at.shares_end && i + 1 == samples) {
        const Cursor& first = next[k];
        Read(clip_.data.data() + clip_.segment_offsets[at.segment + 1], first, 0, b);
        if (track.kind == TrackKind::kRotation && first.dropped != c.dropped) {
          float q[4], kept[3];
          compression_internal::ExpandRotation(b, first.dropped, q);
          compression_internal::ReduceRotation(q, c.dropped, kept);
          std::copy(kept, kept + 3, b);
        }
      } else {
        Read(clip_.data.data() + clip_.segment_offsets[at.segment], c, i + 1, b);
      }
      if (track.kind == TrackKind::kRotation) {
        StoreRotation(Nlerp(a, b, u, c.dropped), pose[track.joint]);
      } else {
        float r[3];
        for (int d = 0; d < 3; ++d) r[d] = a[d] + u * (b[d] - a[d]);
        Store(track.kind, r, pose[track.joint]);
      }
    }
    return pose;
  }

 private:
  struct Position {
    size_t segment = 0, intervals = 0;
    float q = 0;
    bool shares_end = false;
  };
  struct Cursor {
    compression_internal::SampleLayout layout{};
    compression_internal::Dequantizer dequantizer{};
    size_t bit = 0;
    int stride_log = 0, dropped = 3;
  };
  struct Quat {
    float x, y, z, w;
  };

  Position Locate(double t) const {
    const size_t last = clip_.frames.count - 1;
    double p = clip_.frames.frame_time > 0 ? t / clip_.frames.frame_time : 0;
    const double nearest = std::round(p);
    if (std::abs(p - nearest) < 1e-9 * std::max(1.0, p)) p = nearest;
    p = std::clamp(p, 0.0, static_cast<double>(last));
    Position at;
    at.segment =
        std::min(static_cast<size_t>(p) / compression_internal::kSegmentFrames, clip_.segment_offsets.size() - 1);
    const size_t start = at.segment * compression_internal::kSegmentFrames;
    at.intervals = std::min(compression_internal::kSegmentFrames, last - start);
    at.q = static_cast<float>(p - static_cast<double>(start));
    at.shares_end = at.segment + 1 < clip_.segment_offsets.size();
    return at;
  }

  // Every track's cursor in `segment`: codes first, samples after them,
  // per-segment dropped components, ranges and slopes from the segment's end back.
  std::vector<Cursor> Header(size_t segment) const {
    using namespace compression_internal;
    const size_t segments = clip_.segment_offsets.size();
    const uint8_t* data = clip_.data.data() + clip_.segment_offsets[segment];
    const uint8_t* back = clip_.data.data() + (segment + 1 < segments ? clip_.segment_offsets[segment + 1]
                                                                      : clip_.data.size() - kReadPadding);
    const size_t intervals = std::min(kSegmentFrames, clip_.frames.count - 1 - segment * kSegmentFrames);
    const bool shares_end = segment + 1 < segments;
    std::vector<Cursor> cursors(clip_.animated.size());
    size_t bit = clip_.animated.size() * 8;
    for (size_t k = 0; k < cursors.size(); ++k) {
      const AnimatedTrack& track = clip_.animated[k];
      const TrackCode code = kCodes[data[k]];
      Cursor& c = cursors[k];
      c.dropped = track.dropped == kDroppedPerSegment ? *--back : track.dropped;
      const uint8_t *range = nullptr, *slope = nullptr;
      if (code.ranged) range = back -= kRangeBytes;
      if (code.sloped) slope = back -= kSlopeBytes;
      c.layout = MakeLayout(code.bits, track.extent, range);
      c.dequantizer = MakeDequantizer(track.min, track.extent, range, slope, c.layout);
      c.stride_log = code.stride_log;
      c.bit = bit;
      bit += TrackBits(c.layout, code.stride_log, intervals, shares_end);
    }
    return cursors;
  }

  static void Read(const uint8_t* segment, const Cursor& c, size_t i, float* v) {
    compression_internal::ReadSample(segment, c.bit, c.layout, i, c.dequantizer, v);
  }

  // nlerp of two kept triples (the fourth rebuilt), then the rebuilt one put
  // back at `dropped`: x y z w.
  static Quat Nlerp(const float* a, const float* b, float u, int dropped) {
    const float wa = std::sqrt(std::max(1.f - a[0] * a[0] - a[1] * a[1] - a[2] * a[2], 0.f));
    const float wb = std::sqrt(std::max(1.f - b[0] * b[0] - b[1] * b[1] - b[2] * b[2], 0.f));
    const float d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + wa * wb;
    const float ub = d < 0.f ? -u : u, ua = 1.f - u;
    float r[4];
    for (int c = 0; c < 3; ++c) r[c] = ua * a[c] + ub * b[c];
    r[3] = ua * wa + ub * wb;
    const float norm2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3];
    const float inv = 1.f / std::sqrt(norm2);
    float q[4];
    for (int c = 0, k = 0; c < 4; ++c) q[c] = (c == dropped ? r[3] : r[k++]) * inv;
    return {q[0], q[1], q[2], q[3]};
  }

  static void StoreRotation(const Quat& q, Trs& out) {
    out.rotation = Eigen::Quaterniond(q.w, q.x, q.y, q.z);
    out.rotation.coeffs() *= 0.5 * (3.0 - out.rotation.squaredNorm());
  }

  static void Store(TrackKind kind, const float* v, Trs& out) {
    if (kind == TrackKind::kRotation) return StoreRotation({v[0], v[1], v[2], v[3]}, out);
    (kind == TrackKind::kTranslation ? out.translation : out.scale) = Eigen::Vector3d(v[0], v[1], v[2]);
  }

  const CompressedClip& clip_;
};

}  // namespace armature::test_util
