#include "armature/engine/anim/compression/clip_sampling_job.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

#include "anim/compression/header_reader.h"
#include "anim/compression/packed_track.h"
#include "anim/compression/rotation_batch.h"
#include "anim/compression/sample_reader.h"
#include "anim/compression/sampling_isa.h"

namespace armature {
namespace {

using compression_internal::HeaderReader;
using compression_internal::kSegmentFrames;
using compression_internal::v4;

// A ClipJointSubset's parts, as the sampler reads them.
struct ClipJointSubsetView {
  std::span<const uint32_t> joints, constants, animated;
  std::span<const uint8_t> in_subset;
};

// Where a clip time falls among the packed segments.
struct SegmentPosition {
  size_t segment = 0;
  size_t intervals = 0;     // frames − 1 in the segment
  float q = 0;              // frame position inside it, in [0, intervals]
  bool shares_end = false;  // its last frame is the next segment's first (packed_track.h)
};

ARMATURE_DECODE_INLINE SegmentPosition Locate(const CompressedClip& clip, double t) {
  const size_t last = clip.frames.count - 1;
  double p = clip.frames.frame_time > 0 ? t / clip.frames.frame_time : 0;
  p = std::clamp(p, 0.0, static_cast<double>(last));
  // A frame's own time lands on its frame, not just before it (p ≥ 0: a
  // truncation rounds it, without libm's round).
  const double nearest = static_cast<double>(static_cast<size_t>(p + 0.5));
  if (std::abs(p - nearest) < 1e-9 * std::max(1.0, p)) p = nearest;
  SegmentPosition at;
  at.segment = std::min(static_cast<size_t>(p) / kSegmentFrames, clip.segment_offsets.size() - 1);
  const size_t start = at.segment * kSegmentFrames;
  at.intervals = std::min(kSegmentFrames, last - start);
  at.q = static_cast<float>(p - static_cast<double>(start));
  at.shares_end = at.segment + 1 < clip.segment_offsets.size();
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

// The interval (first sample) a track's stride puts position `at` in.
inline size_t IntervalOf(const TrackCursor& cursor, const SegmentPosition& at) {
  const size_t last = (at.intervals >> cursor.stride_log) - 1;
  return std::min(static_cast<size_t>(at.q) >> cursor.stride_log, last);
}

// True when that interval ends on the next segment's first sample.
inline bool EndsOnNext(const TrackCursor& cursor, const SegmentPosition& at, size_t i) {
  return at.shares_end && i + 1 == (at.intervals >> cursor.stride_log);
}

// Where decoded tracks go: double transforms (ClipSamplingJob)...
struct TrsSink {
  std::span<Trs> out;
  compression_internal::RotationBatch rotations;

  ARMATURE_DECODE_INLINE void Rotation(v4 a, v4 b, float u, int dropped, uint32_t joint) {
    rotations.Add(a, b, u, dropped, &out[joint]);
  }
  void Vector(TrackKind kind, v4 v, uint32_t joint) {
    (kind == TrackKind::kTranslation ? out[joint].translation : out[joint].scale) = Eigen::Vector3d(v[0], v[1], v[2]);
  }
  ARMATURE_DECODE_INLINE void Flush() { rotations.Flush(); }
};

// ...or float lanes (ClipSamplingFloatJob).
struct FloatSink {
  FloatPose out;
  compression_internal::RotationBatchOf<float> rotations;

  ARMATURE_DECODE_INLINE void Rotation(v4 a, v4 b, float u, int dropped, uint32_t joint) {
    rotations.Add(a, b, u, dropped, &out.rotations[4 * joint]);
  }
  void Vector(TrackKind kind, v4 v, uint32_t joint) {
    float* to = (kind == TrackKind::kTranslation ? out.translations : out.scales).data() + 3 * joint;
    to[0] = v[0], to[1] = v[1], to[2] = v[2];
  }
  ARMATURE_DECODE_INLINE void Flush() { rotations.Flush(); }
};

// One animated track at segment position `at`: its two samples around q,
// interpolated.
template <class Sink>
ARMATURE_DECODE_INLINE void DecodeTrack(const AnimatedTrack& track, const TrackCursor& cursor, const uint8_t* segment,
                                        const SegmentPosition& at, Sink& sink) {
  using compression_internal::ReadKept;
  const size_t i = IntervalOf(cursor, at);
  const float u =
      (at.q - static_cast<float>(i << cursor.stride_log)) * compression_internal::kInverseStride[cursor.stride_log];
  const size_t bit_a = cursor.bit + i * cursor.total;
  const float fi = static_cast<float>(i);
  const v4 a = ReadKept(segment, bit_a, fi, cursor);
  // The data is padded (kReadPadding), so the read past a segment's last
  // sample is harmless; its shared end replaces it.
  const v4 b = EndsOnNext(cursor, at, i) ? compression_internal::Load4(cursor.end)
                                         : ReadKept(segment, bit_a + cursor.total, fi + 1.f, cursor);
  if (track.kind == TrackKind::kRotation) return sink.Rotation(a, b, u, cursor.dropped, track.joint);
  sink.Vector(track.kind, a + compression_internal::Splat(u) * (b - a), track.joint);
}

// `cursor.end` from the next segment's first sample of the track (its
// cursor `first`), in `cursor`'s kept components.
ARMATURE_DECODE_INLINE void ReadEnd(TrackKind kind, const TrackCursor& first, const uint8_t* next,
                                    TrackCursor& cursor) {
  using namespace compression_internal;
  const v4 v = ReadKept(next, first.bit, 0.f, first);  // lane 3 is 0, as `end`'s fourth stays
  if (kind != TrackKind::kRotation || first.dropped == cursor.dropped) return Store4(cursor.end, v);
  const float kept[3] = {v[0], v[1], v[2]};
  float q[4];
  ExpandRotation(kept, first.dropped, q);
  ReduceRotation(q, cursor.dropped, cursor.end);
}

// Reads the ends of the tracks that `at` interpolates toward, walking the
// next segment's header only as far as the last of them.
ARMATURE_DECODE_INLINE void ReadNeededEnds(const CompressedClip& clip, const SegmentPosition& at,
                                           std::span<TrackCursor> cursors) {
  size_t through = 0;
  for (size_t t = 0; t < cursors.size(); ++t)
    if (EndsOnNext(cursors[t], at, IntervalOf(cursors[t], at))) through = t + 1;
  HeaderReader next(clip, at.segment + 1);
  TrackCursor first;
  for (size_t t = 0; t < through; ++t) {
    const bool needed = EndsOnNext(cursors[t], at, IntervalOf(cursors[t], at));
    next.Next(t, first, needed);
    if (needed) ReadEnd(clip.animated[t].kind, first, next.data(), cursors[t]);
  }
}

// The context's cursors for `at`. Playback (segments in order) takes the
// cursors read for the previous segment's ends and reads every end at
// once; a seek reads only the ends its position needs, and every end once
// a later position needs more.
ARMATURE_DECODE_INLINE void IndexSegment(const CompressedClip& clip, const SegmentPosition& at, SegmentIndex& index) {
  const size_t tracks = clip.animated.size();
  if (index.segment != at.segment) {
    const bool in_order = index.segment + 1 == at.segment;
    if (index.next_segment == at.segment) {
      index.tracks.swap(index.next);
    } else {
      HeaderReader reader(clip, at.segment);
      for (size_t i = 0; i < tracks; ++i) reader.Next(i, index.tracks[i]);
    }
    index.next_segment = static_cast<size_t>(-1);
    index.segment = at.segment;
    index.ends_q = -1;
    if (at.shares_end && !in_order) {
      ReadNeededEnds(clip, at, index.tracks);
      index.ends_q = at.q;
    }
  }
  if (!at.shares_end || at.q <= index.ends_q) return;
  HeaderReader next(clip, at.segment + 1);
  for (size_t i = 0; i < tracks; ++i) {
    next.Next(i, index.next[i]);
    ReadEnd(clip.animated[i].kind, index.next[i], next.data(), index.tracks[i]);
  }
  index.next_segment = at.segment + 1;
  index.ends_q = static_cast<float>(kSegmentFrames);
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

// The same as float lanes, from the context's (`still`, 10 floats a joint).
void StoreStillLanes(std::span<const float> still, const ClipJointSubsetView* subset, const FloatPose& out) {
  const size_t joints = out.scales.size() / 3;
  const float *rotations = still.data(), *translations = rotations + 4 * joints, *scales = rotations + 7 * joints;
  if (!subset) {
    std::copy(rotations, rotations + 4 * joints, out.rotations.begin());
    std::copy(translations, translations + 3 * joints, out.translations.begin());
    std::copy(scales, scales + 3 * joints, out.scales.begin());
    return;
  }
  for (uint32_t j : subset->joints) {  // loops, not std::copy: a library call per 12 bytes costs more than the copy
    for (int c = 0; c < 4; ++c) out.rotations[4 * j + c] = rotations[4 * j + c];
    for (int c = 0; c < 3; ++c) {
      out.translations[3 * j + c] = translations[3 * j + c];
      out.scales[3 * j + c] = scales[3 * j + c];
    }
  }
}

// The animated tracks at `t` into `sink` (the still pose is the caller's).
template <class Sink>
ARMATURE_DECODE_INLINE void SampleLossyBody(const CompressedClip& clip, double t, SegmentIndex* index,
                                            const ClipJointSubsetView* subset, Sink& sink) {
  if (clip.animated.empty()) return;
  const SegmentPosition at = Locate(clip, t);
  const size_t tracks = clip.animated.size();
  const uint8_t* segment = clip.data.data() + clip.segment_offsets[at.segment];
  if (!index) {  // random access: each track's cursor, used at once
    HeaderReader reader(clip, at.segment);
    // The next segment's header is read in step, for the shared ends (the
    // last segment has none: it reads its own again, unused). Both walk
    // every track; only the subset's are decoded.
    HeaderReader next(clip, at.shares_end ? at.segment + 1 : at.segment);
    TrackCursor cursor, first;
    for (size_t i = 0; i < tracks; ++i) {
      reader.Next(i, cursor);
      const bool wanted = !subset || subset->in_subset[i];
      const bool needed = wanted && EndsOnNext(cursor, at, IntervalOf(cursor, at));
      next.Next(i, first, needed);
      if (needed) ReadEnd(clip.animated[i].kind, first, next.data(), cursor);
      if (wanted) DecodeTrack(clip.animated[i], cursor, segment, at, sink);
    }
    return sink.Flush();
  }
  IndexSegment(clip, at, *index);
  if (subset) {
    for (uint32_t i : subset->animated) DecodeTrack(clip.animated[i], index->tracks[i], segment, at, sink);
  } else {
    for (size_t i = 0; i < tracks; ++i) DecodeTrack(clip.animated[i], index->tracks[i], segment, at, sink);
  }
  sink.Flush();
}

#if ARMATURE_SAMPLING_AVX2
// On a CPU with AVX2 and BMI2, SampleLossy runs this clone: the same code
// with VEX's three-operand forms and BMI2's shifts by any register (the
// bit reads), 3–5% faster in sequence and 8–9% at random on CMU 01_01. It
// is built without FMA, so it does the same float operations and gives
// the same values (decode_reference_test runs both builds against the
// plain decoder; sampling_isa.h switches). Its target is an attribute, not
// a flag for the file, so Eigen's alignment and Trs's layout stay those of
// every other file.
template <class Sink>
[[gnu::target("avx2,bmi,bmi2,lzcnt,popcnt")]] void SampleLossyAvx2(const CompressedClip& clip, double t,
                                                                   SegmentIndex* index,
                                                                   const ClipJointSubsetView* subset, Sink& sink) {
  SampleLossyBody(clip, t, index, subset, sink);
}
#endif

// Read on every call, written only by UseSamplingAvx2 (tests): relaxed.
std::atomic<bool> sample_with_avx2{compression_internal::CpuRunsSamplingAvx2()};

template <class Sink>
void SampleLossy(const CompressedClip& clip, double t, SegmentIndex* index, const ClipJointSubsetView* subset,
                 Sink& sink) {
#if ARMATURE_SAMPLING_AVX2
  if (sample_with_avx2.load(std::memory_order_relaxed)) return SampleLossyAvx2(clip, t, index, subset, sink);
#endif
  SampleLossyBody(clip, t, index, subset, sink);
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
  index_.next_segment = static_cast<size_t>(-1);
  index_.next.assign(clip.animated.size(), TrackCursor{});
  clip_pose_.assign(clip.skeleton ? clip.skeleton->size() : 0, Trs{});
  still_pose_ = clip_pose_;
  const size_t joints = clip_pose_.size();
  still_.assign(10 * joints, 0.f);
  if (!clip.skeleton) return;
  StoreStill(clip, nullptr, still_pose_);
  for (size_t j = 0; j < joints; ++j) {
    const Trs& p = still_pose_[j];
    const double r[4] = {p.rotation.x(), p.rotation.y(), p.rotation.z(), p.rotation.w()};
    for (int c = 0; c < 4; ++c) still_[4 * j + c] = static_cast<float>(r[c]);
    for (int c = 0; c < 3; ++c) {
      still_[4 * joints + 3 * j + c] = static_cast<float>(p.translation[c]);
      still_[7 * joints + 3 * j + c] = static_cast<float>(p.scale[c]);
    }
  }
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
  if (context && !subset) {  // built once: constant rotations are made unit on Resize, not on every call
    // One block copy: a Trs is doubles (and padding) only, and copying
    // it member by member through Eigen took about a tenth of a call.
    static_assert(std::is_trivially_destructible_v<Trs>);
    if (!output.empty())
      std::memcpy(static_cast<void*>(output.data()), context->still_pose_.data(), output.size() * sizeof(Trs));
  } else {
    StoreStill(*clip, subset ? &*subset : nullptr, output);
  }
  TrsSink sink{output, {}};
  SampleLossy(*clip, interpolation == Interpolation::kStep ? FrameAtOrBefore(*clip, t) : t,
              context ? &context->index_ : nullptr, subset ? &*subset : nullptr, sink);
  return Status::Ok();
}

Status ClipSamplingFloatJob::Validate() const {
  ARMATURE_RETURN_IF_ERROR(CheckClip(clip));
  ARMATURE_RETURN_IF_ERROR(CheckTime(time, wrap, std::nullopt));
  if (!context || !context->Fits(*clip))
    return Status::InvalidArgument("float sampling job: needs a context resized to the clip");
  const size_t count = clip->skeleton->size();
  if (output.rotations.size() != 4 * count || output.translations.size() != 3 * count ||
      output.scales.size() != 3 * count)
    return Status::InvalidArgument("float sampling job: output lanes of " + std::to_string(output.rotations.size()) +
                                   ", " + std::to_string(output.translations.size()) + ", " +
                                   std::to_string(output.scales.size()) + " floats for " + std::to_string(count) +
                                   " joints (4, 3, 3 a joint)");
  if (joints && !joints->Fits(*clip))
    return Status::InvalidArgument("float sampling job: the joint subset was not built for this clip");
  return Status::Ok();
}

Status ClipSamplingFloatJob::Run() const {
  ARMATURE_RETURN_IF_ERROR(Validate());
  const size_t count = clip->skeleton->size();
  if (clip->exact()) {  // sampled in double, then narrowed
    ARMATURE_RETURN_IF_ERROR((ClipSamplingJob{clip, time, wrap, context, context->clip_pose_, std::nullopt}.Run()));
    for (size_t j = 0; j < count; ++j) {
      const Trs& p = context->clip_pose_[j];
      const double r[4] = {p.rotation.x(), p.rotation.y(), p.rotation.z(), p.rotation.w()};
      for (int c = 0; c < 4; ++c) output.rotations[4 * j + c] = static_cast<float>(r[c]);
      for (int c = 0; c < 3; ++c) {
        output.translations[3 * j + c] = static_cast<float>(p.translation[c]);
        output.scales[3 * j + c] = static_cast<float>(p.scale[c]);
      }
    }
    return Status::Ok();
  }
  std::optional<ClipJointSubsetView> subset;
  if (joints) subset = ClipJointSubsetView{joints->joints_, joints->constants_, joints->animated_, joints->in_subset_};
  if (!still_written) StoreStillLanes(context->still_, subset ? &*subset : nullptr, output);
  FloatSink sink{output, {}};
  SampleLossy(*clip, WrapTime(time, clip->duration, wrap), &context->index_, subset ? &*subset : nullptr, sink);
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

namespace compression_internal {

bool CpuRunsSamplingAvx2() {
#if ARMATURE_SAMPLING_AVX2
  __builtin_cpu_init();  // it may be asked before libgcc's own initializer ran
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("bmi2");
#else
  return false;
#endif
}
bool SamplingUsesAvx2() { return sample_with_avx2.load(std::memory_order_relaxed); }
void UseSamplingAvx2(bool on) { sample_with_avx2.store(on && CpuRunsSamplingAvx2(), std::memory_order_relaxed); }

}  // namespace compression_internal

}  // namespace armature
