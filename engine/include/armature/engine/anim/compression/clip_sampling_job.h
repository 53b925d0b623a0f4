// The one way to sample a compressed clip, in ozz's style: a job holds its
// inputs and output span, Validate() checks them, Run() samples with no
// allocation. A context carries what sequential playback reuses from one
// call to the next; a joint map plays the clip on another skeleton.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "armature/base/status.h"
#include "armature/engine/anim/clip.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/math/transform.h"

namespace armature {

// One animated track in one segment, read from its header: where its
// samples start, their bits per component, its stride, the component a
// rotation rebuilds, and sample i's value = (offset + scale · q) + i · slope
// per component (packed_track.h's Dequantizer); `end`:
// the segment's last frame, the next segment's first sample as it decodes
// it, in this segment's kept components (when the segment has a next).
// The float triples have a fourth lane, kept 0, so the job reads each as a
// vector.
struct TrackCursor {
  uint32_t bit = 0;
  uint8_t bits[3] = {};
  uint8_t total = 0;
  uint8_t stride_log = 0;
  uint8_t dropped = 3;
  float offset[4] = {}, scale[4] = {}, slope[4] = {};
  float end[4] = {};
};

// Every animated track's cursor in one segment.
// `next`: the following segment's cursors once read (its first samples are
// this segment's ends), reused when playback moves on to it. `ends_q`: the
// position through which the tracks' ends are read (a seek reads only those
// it needs; every one once playback goes past it).
struct SegmentIndex {
  size_t segment = static_cast<size_t>(-1);
  std::vector<TrackCursor> tracks;
  size_t next_segment = static_cast<size_t>(-1);
  std::vector<TrackCursor> next;
  float ends_q = 0;
};

// Per-playback state: the segment last sampled and where each animated
// track's samples start in it, and the clip-skeleton pose a joint map reads.
// Resize it to the clip once (allocates); jobs then reuse it.
class ClipSamplingContext {
 public:
  ClipSamplingContext() = default;
  explicit ClipSamplingContext(const CompressedClip& clip) { Resize(clip); }
  void Resize(const CompressedClip& clip);
  // Resized to this very clip (not one freed before it at the same address).
  bool Fits(const CompressedClip& clip) const;

 private:
  friend struct ClipSamplingJob;
  friend struct ClipSamplingOntoJob;
  friend struct ClipSamplingFloatJob;
  const CompressedClip* clip_ = nullptr;
  uint64_t serial_ = 0;
  SegmentIndex index_;
  std::vector<Trs> clip_pose_;   // for ClipSamplingOntoJob
  std::vector<Trs> still_pose_;  // rest and constant tracks, every joint (ClipSamplingJob)
  std::vector<float> still_;     // for ClipSamplingFloatJob: rest and constants as its lanes (4, 3, 3 a joint)
};

// A subset of a clip's joints to sample, resolved once (allocates) into the
// clip's tracks on them, so a job decodes nothing else: a masked motion
// layer samples only the joints it acts on.
class ClipJointSubset {
 public:
  ClipJointSubset() = default;
  // `joints` are the clip's joint indices (each < its skeleton's size).
  ClipJointSubset(const CompressedClip& clip, std::span<const uint32_t> joints);
  bool Fits(const CompressedClip& clip) const;

 private:
  friend struct ClipSamplingJob;
  friend struct ClipSamplingFloatJob;
  const CompressedClip* clip_ = nullptr;
  uint64_t serial_ = 0;
  std::vector<uint32_t> joints_;     // ascending, unique
  std::vector<uint32_t> constants_;  // indices into clip.constants on those joints
  std::vector<uint32_t> animated_;   // indices into clip.animated on those joints
  std::vector<uint8_t> in_subset_;   // per animated track: 1 when on one of those joints
};

// Samples every joint's local transform at `time` into `output` (size =
// the clip's joints), or only `joints`' when given (the other transforms
// are left as they were, except on an exact clip, which writes all). Between frames rotations are nlerped (the stride's
// samples and the frames alike), then made unit in double (one Newton step);
// an exact clip samples as SampleClip. `interpolation` overrides the tracks'
// own: on an exact clip as SampleClip's; on a lossy one STEP holds the frame
// at or before `time`, LINEAR and CUBIC interpolate between frames (the bound
// holds at frames, as ACL measures it).
struct ClipSamplingJob {
  const CompressedClip* clip = nullptr;
  double time = 0;
  WrapMode wrap = WrapMode::kClamp;
  ClipSamplingContext* context = nullptr;  // optional: sequential playback reuses it
  std::span<Trs> output;
  std::optional<Interpolation> interpolation;
  const ClipJointSubset* joints = nullptr;  // optional: built for this clip

  Status Validate() const;
  Status Run() const;  // Validate(), then samples
};

// A local pose in float lanes: per joint x y z w (rotations), x y z
// (translations, scales).
struct FloatPose {
  std::span<float> rotations, translations, scales;
};

// ClipSamplingJob's LINEAR sampling into float lanes, for callers that want
// float32 anyway (the crowd's wire): no double transforms, rotations nlerped
// and made unit in float (no Newton step; |q| − 1 stays near 1e-7). An exact
// clip is sampled in double and narrowed. Needs a context (it holds the
// still pose, rest and constant tracks, as lanes). No allocation in Run.
// `joints`, as ClipSamplingJob's: only those joints' lanes are written (a
// motion's float-lane blend samples each layer at the joints it reads).
struct ClipSamplingFloatJob {
  const CompressedClip* clip = nullptr;
  double time = 0;
  WrapMode wrap = WrapMode::kClamp;
  ClipSamplingContext* context = nullptr;
  FloatPose output;
  const ClipJointSubset* joints = nullptr;  // optional: built for this clip
  // The output already holds the still pose (rest and constant tracks) at
  // those joints, as a job without it wrote there before: only the animated
  // tracks are written (a motion layer's lanes, reused from pose to pose).
  bool still_written = false;

  Status Validate() const;
  Status Run() const;
};

// The same on `target`, through `map` (MapJointsByName(target,
// *clip->skeleton), anim/joint_map.h): each joint starts at target's rest
// and its clip joint replaces what the clip animates. Needs a context.
struct ClipSamplingOntoJob {
  const CompressedClip* clip = nullptr;
  std::span<const int> map;
  const Skeleton* target = nullptr;
  double time = 0;
  WrapMode wrap = WrapMode::kClamp;
  ClipSamplingContext* context = nullptr;
  std::span<Trs> output;
  std::optional<Interpolation> interpolation;

  Status Validate() const;
  Status Run() const;
};

}  // namespace armature
