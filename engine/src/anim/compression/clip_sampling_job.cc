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

// A ClipJointSubset's parts, as the sampler reads them.
struct ClipJointSubsetView {
  std::span<const uint32_t> joints, constants, animated;
  std::span<const uint8_t> in_subset;
};

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
      compression_internal::MakeUnit(out.rotation);
      break;
    case TrackKind::kTranslation: out.translation = Eigen::Vector3d(v[0], v[1], v[2]); break;
    case TrackKind::kScale: out.scale = Eigen::Vector3d(v[0], v[1], v[2]); break;
  }
}

// One animated track at segment position `at`: its two samples around q,
// interpolated.
inline void DecodeTrack(const AnimatedTrack& track, const TrackCursor& cursor, const uint8_t* segment,
                        const SegmentPosition& at, Trs& out, compression_internal::RotationBatch& rotations) {
  using compression_internal::ReadBits;
  const size_t last = (at.intervals >> cursor.stride_log) - 1;
  const size_t i = std::min(static_cast<size_t>(at.q) >> cursor.stride_log, last);
  const float u =
      (at.q - static_cast<float>(i << cursor.stride_log)) * compression_internal::kInverseStride[cursor.stride_log];
  float a[3], b[3];
  size_t bit_a = cursor.bit + i * cursor.total, bit_b = bit_a + cursor.total;
  for (int c = 0; c < 3; ++c) {
    a[c] = cursor.offset[c] + cursor.scale[c] * static_cast<float>(ReadBits(segment, bit_a, cursor.bits[c]));
    b[c] = cursor.offset[c] + cursor.scale[c] * static_cast<float>(ReadBits(segment, bit_b, cursor.bits[c]));
    bit_a += cursor.bits[c];
    bit_b += cursor.bits[c];
  }
  if (track.kind == TrackKind::kRotation) return rotations.Add(a, b, u, cursor.dropped, &out);
  float r[3];
  for (int c = 0; c < 3; ++c) r[c] = a[c] + u * (b[c] - a[c]);
  Store(track.kind, r, out);
}

// Reads a segment's header into a cursor per track: `cursor_of(track)` says
// where (written in place: a cursor built aside and copied stalls on store
// forwarding), then `visit(track, cursor)`.
template <class CursorOf, class Visit>
void WalkSegment(const CompressedClip& clip, const uint8_t* segment, const uint8_t* end, size_t intervals,
                 const CursorOf& cursor_of, const Visit& visit) {
  using namespace compression_internal;
  const size_t tracks = clip.animated.size();
  size_t bit = tracks * 8;
  const uint8_t* back = end;  // dropped components and ranges, from the end, in track order
  for (size_t t = 0; t < tracks; ++t) {
    const AnimatedTrack& track = clip.animated[t];
    const TrackCode code = kCodes[segment[t]];
    TrackCursor& cursor = cursor_of(t);
    cursor.dropped = track.dropped == kDroppedPerSegment ? *--back : track.dropped;
    const uint8_t* range = code.ranged ? (back -= kRangeBytes) : nullptr;
    cursor.total = FillLayout(code.bits, track.extent, range, cursor.bits);
    FillDequantizer(track.min, track.extent, range, cursor.bits, cursor.offset, cursor.scale);
    cursor.bit = static_cast<uint32_t>(bit);
    cursor.stride_log = code.stride_log;
    visit(t, cursor);
    bit += static_cast<size_t>(cursor.total) * ((intervals >> code.stride_log) + 1);
  }
}

// The rest pose and the constant tracks: of every joint, or of the subset's.
void StoreStill(const CompressedClip& clip, const ClipJointSubsetView* subset, std::span<Trs> out) {
  const Skeleton& skeleton = *clip.skeleton;
  if (!subset) {
    std::copy(skeleton.rest.begin(), skeleton.rest.end(), out.begin());
    for (const ConstantTrack& c : clip.constants) Store(c.kind, c.value, out[c.joint]);
    return;
  }
  for (uint32_t j : subset->joints) out[j] = skeleton.rest[j];
  for (uint32_t i : subset->constants)
    Store(clip.constants[i].kind, clip.constants[i].value, out[clip.constants[i].joint]);
}

void SampleLossy(const CompressedClip& clip, double t, SegmentIndex* index, const ClipJointSubsetView* subset,
                 std::span<Trs> out) {
  StoreStill(clip, subset, out);
  if (clip.animated.empty()) return;
  const SegmentPosition at = Locate(clip, t);
  const uint8_t* segment = clip.data.data() + clip.segment_offsets[at.segment];
  const uint8_t* end = clip.data.data() + (at.segment + 1 < clip.segment_offsets.size()
                                               ? clip.segment_offsets[at.segment + 1]
                                               : clip.data.size() - compression_internal::kReadPadding);
  compression_internal::RotationBatch rotations;
  if (!index) {
    TrackCursor cursor;
    WalkSegment(
        clip, segment, end, at.intervals, [&](size_t) -> TrackCursor& { return cursor; },
        [&](size_t i, const TrackCursor& c) {
          if (!subset || subset->in_subset[i])
            DecodeTrack(clip.animated[i], c, segment, at, out[clip.animated[i].joint], rotations);
        });
    return rotations.Flush();
  }
  if (index->segment != at.segment) {  // sequential playback: each segment's header is read once
    WalkSegment(
        clip, segment, end, at.intervals, [&](size_t i) -> TrackCursor& { return index->tracks[i]; },
        [](size_t, const TrackCursor&) {});
    index->segment = at.segment;
  }
  if (subset) {
    for (uint32_t i : subset->animated)
      DecodeTrack(clip.animated[i], index->tracks[i], segment, at, out[clip.animated[i].joint], rotations);
  } else {
    for (size_t i = 0; i < clip.animated.size(); ++i)
      DecodeTrack(clip.animated[i], index->tracks[i], segment, at, out[clip.animated[i].joint], rotations);
  }
  rotations.Flush();
}

// STEP on a lossy clip: the time of the frame at or before `t` (a frame's
// own time, within rounding, is that frame).
double FrameAtOrBefore(const CompressedClip& clip, double t) {
  if (!(clip.frames.frame_time > 0)) return 0;
  const double p = t / clip.frames.frame_time;
  return clip.frames.Time(static_cast<size_t>(std::floor(p + 1e-9 * std::max(1.0, p))));
}

Status CheckClip(const CompressedClip* clip) {
  if (!clip) return Status::InvalidArgument("sampling job: no clip");
  if (!clip->skeleton) return Status::InvalidArgument("sampling job: the clip has no skeleton");
  if (!clip->exact() && (clip->frames.count == 0 || (!clip->animated.empty() && clip->segment_offsets.empty())))
    return Status::InvalidArgument("sampling job: the clip has no frames");
  return Status::Ok();
}

Status CheckTime(double time, WrapMode wrap, const std::optional<Interpolation>& interpolation) {
  if (!std::isfinite(time)) return Status::InvalidArgument("sampling job: time is not finite");
  if (interpolation && *interpolation != Interpolation::kStep && *interpolation != Interpolation::kLinear &&
      *interpolation != Interpolation::kCubic)
    return Status::InvalidArgument("sampling job: interpolation " + std::to_string(static_cast<int>(*interpolation)) +
                                   " is not STEP, LINEAR or CUBIC");
  if (wrap != WrapMode::kClamp && wrap != WrapMode::kLoop)
    return Status::InvalidArgument("sampling job: wrap mode " + std::to_string(static_cast<int>(wrap)) +
                                   " is not CLAMP or LOOP");
  return Status::Ok();
}

}  // namespace

void ClipSamplingContext::Resize(const CompressedClip& clip) {
  clip_ = &clip;
  serial_ = clip.serial;
  index_.segment = static_cast<size_t>(-1);
  index_.tracks.assign(clip.animated.size(), TrackCursor{});
  clip_pose_.assign(clip.skeleton ? clip.skeleton->size() : 0, Trs{});
}

bool ClipSamplingContext::Fits(const CompressedClip& clip) const { return clip_ == &clip && serial_ == clip.serial; }

ClipJointSubset::ClipJointSubset(const CompressedClip& clip, std::span<const uint32_t> joints)
    : clip_(&clip), serial_(clip.serial), joints_(joints.begin(), joints.end()) {
  std::sort(joints_.begin(), joints_.end());
  joints_.erase(std::unique(joints_.begin(), joints_.end()), joints_.end());
  std::vector<uint8_t> chosen(clip.skeleton ? clip.skeleton->size() : 0, 0);
  for (uint32_t j : joints_)
    if (j < chosen.size()) chosen[j] = 1;
  for (size_t i = 0; i < clip.constants.size(); ++i)
    if (chosen[clip.constants[i].joint]) constants_.push_back(static_cast<uint32_t>(i));
  in_subset_.assign(clip.animated.size(), 0);
  for (size_t i = 0; i < clip.animated.size(); ++i)
    if (chosen[clip.animated[i].joint]) {
      animated_.push_back(static_cast<uint32_t>(i));
      in_subset_[i] = 1;
    }
}

bool ClipJointSubset::Fits(const CompressedClip& clip) const {
  return clip_ == &clip && serial_ == clip.serial && (joints_.empty() || joints_.back() < clip.skeleton->size());
}

Status ClipSamplingJob::Validate() const {
  ARMATURE_RETURN_IF_ERROR(CheckClip(clip));
  ARMATURE_RETURN_IF_ERROR(CheckTime(time, wrap, interpolation));
  if (output.size() != clip->skeleton->size())
    return Status::InvalidArgument("sampling job: output has room for " + std::to_string(output.size()) +
                                   " transforms, the skeleton has " + std::to_string(clip->skeleton->size()) +
                                   " joints");
  if (context && !context->Fits(*clip))
    return Status::InvalidArgument("sampling job: the context was not resized to this clip");
  if (joints && !joints->Fits(*clip))
    return Status::InvalidArgument("sampling job: the joint subset was not built for this clip");
  return Status::Ok();
}

Status ClipSamplingJob::Run() const {
  ARMATURE_RETURN_IF_ERROR(Validate());
  const double t = WrapTime(time, clip->duration, wrap);
  if (clip->exact()) return SampleClip(*clip->exact_keys, t, {interpolation, WrapMode::kClamp}, output);
  std::optional<ClipJointSubsetView> subset;
  if (joints) subset = ClipJointSubsetView{joints->joints_, joints->constants_, joints->animated_, joints->in_subset_};
  SampleLossy(*clip, interpolation == Interpolation::kStep ? FrameAtOrBefore(*clip, t) : t,
              context ? &context->index_ : nullptr, subset ? &*subset : nullptr, output);
  return Status::Ok();
}

Status ClipSamplingOntoJob::Validate() const {
  ARMATURE_RETURN_IF_ERROR(CheckClip(clip));
  ARMATURE_RETURN_IF_ERROR(CheckTime(time, wrap, interpolation));
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
  ClipSamplingJob own{clip, time, wrap, context, context->clip_pose_, interpolation};
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
