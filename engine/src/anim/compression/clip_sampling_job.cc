#include "armature/engine/anim/compression/clip_sampling_job.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "anim/compression/packed_track.h"
#include "anim/compression/rotation_batch.h"

namespace armature {
namespace {

using compression_internal::kCodes;
using compression_internal::kRangeBytes;
using compression_internal::kSegmentFrames;
using compression_internal::TrackCode;

constexpr uint32_t kNoRange = 0xffffffffu;

// Where a clip time falls among the packed segments.
struct SegmentPosition {
  size_t segment = 0;
  size_t intervals = 0;  // frames − 1 in the segment
  float q = 0;           // frame position inside it, in [0, intervals]
};

SegmentPosition Locate(const CompressedClip& clip, double t) {
  const size_t last = clip.frames.count - 1;
  double p = clip.frames.frame_time > 0 ? t / clip.frames.frame_time : 0;
  const double nearest = std::round(p);  // a frame's own time lands on its frame, not just before it
  if (std::abs(p - nearest) < 1e-9 * std::max(1.0, p)) p = nearest;
  p = std::clamp(p, 0.0, static_cast<double>(last));
  SegmentPosition at;
  at.segment = std::min(static_cast<size_t>(p) / kSegmentFrames, clip.segment_offsets.size() - 1);
  const size_t start = at.segment * kSegmentFrames;
  at.intervals = std::min(kSegmentFrames, last - start);
  at.q = static_cast<float>(p - static_cast<double>(start));
  return at;
}

void Store(TrackKind kind, const float* v, Trs& out) {
  switch (kind) {
    case TrackKind::kRotation:
      out.rotation = Eigen::Quaterniond(v[3], v[0], v[1], v[2]);
      break;
    case TrackKind::kTranslation:
      out.translation = Eigen::Vector3d(v[0], v[1], v[2]);
      break;
    case TrackKind::kScale:
      out.scale = Eigen::Vector3d(v[0], v[1], v[2]);
      break;
  }
}

// One animated track at segment position `at`: its two samples around q,
// interpolated. `range_at` is its range's byte in the segment or kNoRange.
inline void DecodeTrack(const AnimatedTrack& track, TrackCode code, int dropped, const uint8_t* segment,
                        uint32_t range_at, size_t bit, const SegmentPosition& at, Trs& out,
                        compression_internal::RotationBatch& rotations) {
  using namespace compression_internal;
  const Dequantizer d =
      MakeDequantizer(track.min, track.extent, range_at == kNoRange ? nullptr : segment + range_at, code.bits);
  const size_t last = (at.intervals >> code.stride_log) - 1;
  const size_t i = std::min(static_cast<size_t>(at.q) >> code.stride_log, last);
  const float u = (at.q - static_cast<float>(i << code.stride_log)) * kInverseStride[code.stride_log];
  float a[4], b[4], r[4];
  ReadSample(segment, bit, code.bits, i, d, a);
  ReadSample(segment, bit, code.bits, i + 1, d, b);
  if (track.kind == TrackKind::kRotation) return rotations.Add(a, b, u, dropped, &out);
  for (int c = 0; c < 3; ++c) r[c] = a[c] + u * (b[c] - a[c]);
  Store(track.kind, r, out);
}

// Walks a segment's header: per track its code, dropped component, range
// byte and first sample bit, handed to `visit(track, code, dropped, range_at, bit)`.
template <class Visit>
void WalkSegment(const CompressedClip& clip, const uint8_t* segment, size_t intervals, const Visit& visit) {
  using compression_internal::kDroppedPerSegment;
  const size_t tracks = clip.animated.size();
  size_t header = tracks;
  for (size_t t = 0; t < tracks; ++t)
    header += (clip.animated[t].dropped == kDroppedPerSegment ? 1 : 0) + (kCodes[segment[t]].ranged ? kRangeBytes : 0);
  size_t at = tracks, bit = header * 8;
  for (size_t t = 0; t < tracks; ++t) {
    const AnimatedTrack& track = clip.animated[t];
    const TrackCode code = kCodes[segment[t]];
    int dropped = track.dropped;
    if (dropped == kDroppedPerSegment) dropped = segment[at++];
    visit(t, code, dropped, code.ranged ? static_cast<uint32_t>(at) : kNoRange, bit);
    if (code.ranged) at += kRangeBytes;
    bit += compression_internal::TrackBits(code, intervals);
  }
}

void SampleLossy(const CompressedClip& clip, double t, SegmentIndex* index, std::span<Trs> out) {
  const Skeleton& skeleton = *clip.skeleton;
  std::copy(skeleton.rest.begin(), skeleton.rest.end(), out.begin());
  for (const ConstantTrack& c : clip.constants) Store(c.kind, c.value, out[c.joint]);
  if (clip.animated.empty()) return;
  const SegmentPosition at = Locate(clip, t);
  const uint8_t* segment = clip.data.data() + clip.segment_offsets[at.segment];
  compression_internal::RotationBatch rotations;
  if (!index) {
    WalkSegment(clip, segment, at.intervals, [&](size_t i, TrackCode code, int dropped, uint32_t range, size_t bit) {
      DecodeTrack(clip.animated[i], code, dropped, segment, range, bit, at, out[clip.animated[i].joint], rotations);
    });
    return rotations.Flush();
  }
  if (index->segment != at.segment) {  // sequential playback: each segment's header is walked once
    WalkSegment(clip, segment, at.intervals, [&](size_t i, TrackCode, int dropped, uint32_t range, size_t bit) {
      index->dropped[i] = static_cast<uint8_t>(dropped);
      index->ranges[i] = range;
      index->bits[i] = static_cast<uint32_t>(bit);
    });
    index->segment = at.segment;
  }
  for (size_t i = 0; i < clip.animated.size(); ++i) {
    const AnimatedTrack& track = clip.animated[i];
    DecodeTrack(track, kCodes[segment[i]], index->dropped[i], segment, index->ranges[i], index->bits[i], at,
                out[track.joint], rotations);
  }
  rotations.Flush();
}

Status CheckClip(const CompressedClip* clip) {
  if (!clip) return Status::InvalidArgument("sampling job: no clip");
  if (!clip->skeleton) return Status::InvalidArgument("sampling job: the clip has no skeleton");
  if (!clip->exact() && (clip->frames.count == 0 || (!clip->animated.empty() && clip->segment_offsets.empty())))
    return Status::InvalidArgument("sampling job: the clip has no frames");
  return Status::Ok();
}

Status CheckTime(double time, WrapMode wrap) {
  if (!std::isfinite(time)) return Status::InvalidArgument("sampling job: time is not finite");
  if (wrap != WrapMode::kClamp && wrap != WrapMode::kLoop)
    return Status::InvalidArgument("sampling job: wrap mode " + std::to_string(static_cast<int>(wrap)) +
                                   " is not CLAMP or LOOP");
  return Status::Ok();
}

}  // namespace

void ClipSamplingContext::Resize(const CompressedClip& clip) {
  clip_ = &clip;
  index_.segment = static_cast<size_t>(-1);
  index_.bits.assign(clip.animated.size(), 0);
  index_.ranges.assign(clip.animated.size(), kNoRange);
  index_.dropped.assign(clip.animated.size(), 3);
  clip_pose_.assign(clip.skeleton ? clip.skeleton->size() : 0, Trs{});
}

bool ClipSamplingContext::Fits(const CompressedClip& clip) const { return clip_ == &clip; }

Status ClipSamplingJob::Validate() const {
  ARMATURE_RETURN_IF_ERROR(CheckClip(clip));
  ARMATURE_RETURN_IF_ERROR(CheckTime(time, wrap));
  if (output.size() != clip->skeleton->size())
    return Status::InvalidArgument("sampling job: output has room for " + std::to_string(output.size()) +
                                   " transforms, the skeleton has " + std::to_string(clip->skeleton->size()) +
                                   " joints");
  if (context && !context->Fits(*clip))
    return Status::InvalidArgument("sampling job: the context was not resized to this clip");
  return Status::Ok();
}

Status ClipSamplingJob::Run() const {
  ARMATURE_RETURN_IF_ERROR(Validate());
  const double t = WrapTime(time, clip->duration, wrap);
  if (clip->exact()) return SampleClip(*clip->exact_keys, t, {}, output);
  SampleLossy(*clip, t, context ? &context->index_ : nullptr, output);
  return Status::Ok();
}

Status ClipSamplingOntoJob::Validate() const {
  ARMATURE_RETURN_IF_ERROR(CheckClip(clip));
  ARMATURE_RETURN_IF_ERROR(CheckTime(time, wrap));
  if (!target) return Status::InvalidArgument("sampling job: no target skeleton");
  if (!context || !context->Fits(*clip))
    return Status::InvalidArgument("sampling job: a joint map needs a context resized to the clip");
  if (map.size() != target->size() || output.size() != target->size())
    return Status::InvalidArgument("joint map of " + std::to_string(map.size()) + " and output of " +
                                   std::to_string(output.size()) + " for a skeleton of " +
                                   std::to_string(target->size()) + " joints");
  const int joints = static_cast<int>(clip->skeleton->size());
  for (size_t j = 0; j < map.size(); ++j)
    if (map[j] < 0 || map[j] >= joints)
      return Status::InvalidArgument("joint map: entry " + std::to_string(j) + " is not a joint of the clip");
  return Status::Ok();
}

Status ClipSamplingOntoJob::Run() const {
  ARMATURE_RETURN_IF_ERROR(Validate());
  ClipSamplingJob own{clip, time, wrap, context, context->clip_pose_};
  ARMATURE_RETURN_IF_ERROR(own.Run());
  for (size_t j = 0; j < target->size(); ++j) {
    const Trs& sampled = context->clip_pose_[static_cast<size_t>(map[j])];
    const uint8_t parts = clip->animated_parts[static_cast<size_t>(map[j])];
    output[j] = target->rest[j];
    if (parts & 1) output[j].rotation = sampled.rotation;
    if (parts & 2) output[j].translation = sampled.translation;
    if (parts & 4) output[j].scale = sampled.scale;
  }
  return Status::Ok();
}

}  // namespace armature
