

#include "armature/engine/anim/compression/compressed_clip.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numeric>
#include <optional>
#include <string>

#include "anim/compression/clip_reference.h"
#include "anim/compression/segment_coder.h"
#include "anim/compression/track_state.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"

namespace armature {
namespace {

using namespace compression_internal;

constexpr double kMinFramesPerSecond = 30;
// A track is kept constant (or dropped as the rest value) when that moves no
// virtual point by more than this share of the bound: the errors of a chain
// add, and the refinement below cannot undo a constant.
constexpr double kConstantShare = 0.05;
// Each animated track's first target, as a share of the bound; segments
// whose measured error is over the bound tighten the tracks of the
// offending joints' chains and choose again.
constexpr double kFirstShare = 1.0;
constexpr int kRefinements = 24;
// A segment over the bound tightens each over joint's chain by the share
// that joint's worst frame is over, with a margin, kept within [kTighten,
// kTightenLeast]: a fixed 0.7 for every chain overshot most segments
// (2.135 B/js on CMU 01_01, against 2.094 now); a fixed 0.85 took 1.6×
// the time.
constexpr double kTighten = 0.7, kTightenLeast = 0.9, kTightenMargin = 0.95;
// (Loosening, after, the targets of tracks whose subtree stays under the
// bound gained 1% on CMU for 40% more time: not done.)

// A track's bytes before its range in a segment: the dropped component of
// a per-segment rotation.
size_t LeadBytes(const AnimatedTrack& track) { return track.dropped == kDroppedPerSegment ? 1 : 0; }

// One segment's bytes as the sampling job reads them (packed_track.h).
void PackSegment(const std::vector<TrackState>& states, const FrameGrid& frames, size_t s, std::vector<uint8_t>& out) {
  const size_t tracks = states.size();
  size_t tail = 0, bits = 0;
  for (const TrackState& st : states) {
    const SegmentTrackChoice& c = st.choice[s];
    tail += LeadBytes(st.track) + TailBytes(c);
    bits += c.bits - 8 * TailBytes(c);
  }
  const size_t size = tracks + (bits + 7) / 8 + tail;
  out.assign(size, 0);
  uint8_t* seg = out.data();
  uint8_t* back = seg + size;  // dropped components, ranges and slopes, from the end, in track order
  size_t bit = tracks * 8;
  for (size_t t = 0; t < tracks; ++t) {
    const SegmentTrackChoice& c = states[t].choice[s];
    seg[t] = c.code;
    if (LeadBytes(states[t].track)) *--back = states[t].dropped[s];
    if (kCodes[c.code].ranged) {
      back -= kRangeBytes;
      std::copy(c.range, c.range + kRangeBytes, back);
    }
    if (kCodes[c.code].sloped) {
      back -= kSlopeBytes;
      std::copy(c.slope, c.slope + kSlopeBytes, back);
    }
    SegmentValues values;
    PackSegmentTrack(SegmentInput(states[t], frames, s, values), c, seg, bit);
    bit += c.bits - 8 * TailBytes(c);
  }
}

// Lays the choices out as the sampling job reads them. `packed` keeps each
// segment's bytes between calls: a segment chosen again empties its own
// (Refiner::ChooseOrExplain), and only those are packed again, as most
// rounds of the refinement choose few segments again.
void Pack(const std::vector<TrackState>& states, std::vector<std::vector<uint8_t>>& packed, CompressedClip& out) {
  const size_t segments = SegmentCount(out.frames.count);
  out.data.clear();
  out.segment_offsets.clear();
  if (states.empty()) return;  // constants only: no segments to keep (the sampling job reads none)
  packed.resize(segments);
  out.segment_offsets.assign(segments, 0);
  for (size_t s = 0; s < segments; ++s) {
    if (packed[s].empty()) PackSegment(states, out.frames, s, packed[s]);
    out.segment_offsets[s] = static_cast<uint32_t>(out.data.size());
    out.data.insert(out.data.end(), packed[s].begin(), packed[s].end());
  }
  out.data.resize(out.data.size() + kReadPadding, 0);
}

// Splits the source's tracks into dropped (rest), constant and animated.
void ClassifyTracks(const ClipReference& reference, double bound, CompressedClip& out,
                    std::vector<TrackState>& animated) {
  const Skeleton& skeleton = *reference.skeleton;
  for (const TrackValues& values : reference.tracks) {
    const uint16_t j = values.joint;
    const TrackKind kind = values.kind;
    const Trs& rest = skeleton.rest[j];
    ConstantTrack rest_value{j, kind, {0, 0, 0, 0}}, first{j, kind, {0, 0, 0, 0}};
    const Eigen::Vector4d r = kind == TrackKind::kRotation ? rest.rotation.normalized().coeffs()
                              : kind == TrackKind::kTranslation
                                  ? Eigen::Vector4d(rest.translation.x(), rest.translation.y(), rest.translation.z(), 0)
                                  : Eigen::Vector4d(rest.scale.x(), rest.scale.y(), rest.scale.z(), 0);
    for (int c = 0; c < 4; ++c) {
      rest_value.value[c] = static_cast<float>(r[c]);
      first.value[c] = static_cast<float>(values.raw[c]);
    }
    if (ConstantFits(values, rest_value.value, kConstantShare * bound)) continue;
    if (ConstantFits(values, first.value, kConstantShare * bound)) {
      out.constants.push_back(first);
      continue;
    }
    animated.push_back(MakeTrackState(values, out.frames, kFirstShare * bound));
  }
}

// Chooses every track's code in `segment` at its target, toward the next
// segment's first samples as now chosen; false when one cannot meet it. A
// track whose target and shared end are what its choice was made for keeps
// it: refinement tightens a few chains, and most tracks of a segment chosen
// again are unchanged (on CMU 01_01, 4,018 of 10,724 choices again).
bool Choose(std::vector<TrackState>& states, const CompressedClip& out, size_t segment) {
  for (TrackState& state : states) {
    const std::array<float, 4> end = state.end[segment];
    UpdateEnd(state, out.frames, segment);
    if (state.chosen_at[segment] == state.target[segment] && state.end[segment] == end) continue;
    SegmentValues values;
    SegmentTrackInput in = SegmentInput(state, out.frames, segment, values);
    const bool fresh = state.choice[segment].bits == 0 && segment + 1 < state.choice.size();
    const SegmentTrackChoice& hint = state.choice[fresh ? segment + 1 : segment];
    if (hint.bits > 0) {
      in.hint_bits = kCodes[hint.code].bits;
      in.hint_stride_log = kCodes[hint.code].stride_log;
    }
    const std::optional<SegmentTrackChoice> c = ChooseSegmentTrack(in, state.target[segment]);
    if (!c) return false;
    state.choice[segment] = *c;
    state.chosen_at[segment] = state.target[segment];
  }
  return true;
}

// Segments last first, each once: a segment ends on the next one's first
// samples, so it is chosen after it.
void SortDescendingUnique(std::vector<size_t>& segments) {
  std::sort(segments.begin(), segments.end(), std::greater<>());
  segments.erase(std::unique(segments.begin(), segments.end()), segments.end());
}

// Multiplies each track's target in `segment` by its joint's factor.
void Tighten(std::vector<TrackState>& states, const std::vector<double>& factors, size_t segment) {
  for (TrackState& s : states) s.target[segment] *= factors[s.values->joint];
}

// The compressor's working state after the first choices: it measures
// segments through the sampling job, and tightens or relaxes targets.
struct Refiner {
  Refiner(const ClipReference& ref, CompressedClip& o, std::vector<TrackState>& st)
      : skeleton(*ref.skeleton), reference(ref), out(o), states(st) {}

  const Skeleton& skeleton;
  const ClipReference& reference;
  CompressedClip& out;
  std::vector<TrackState>& states;
  const size_t segments = SegmentCount(out.frames.count);
  ShellErrorMeter meter{skeleton, out.bound.shell_distance};
  ClipSamplingContext context;
  const size_t joints = skeleton.size();
  std::vector<Trs> pose = std::vector<Trs>(joints), local = pose;  // the job's pose, the reference's
  std::vector<WorldQvv> world = std::vector<WorldQvv>(joints);     // the reference's
  std::vector<double> errors = std::vector<double>(out.frames.count * joints, 0.0);
  std::vector<std::vector<uint8_t>> packed;  // per segment, for Pack
  std::string why;

  // Measures `segment`'s frames through the sampling job into `errors`
  // (frames × joints); the joints over the bound come back, and `late`
  // says whether one is over in the segment's last quarter, near the
  // shared end. `context` was resized to the clip as packed now: the
  // segment's header is walked once, not once a frame.
  std::vector<size_t> MeasureSegment(size_t segment, bool& late) {
    late = false;
    const size_t start = segment * kSegmentFrames;
    const size_t end = segment + 1 == segments ? out.frames.count : start + kSegmentFrames;
    std::vector<size_t> over;
    for (size_t f = start; f < end; ++f) {
      (void)ClipSamplingJob{&out, out.frames.Time(f), WrapMode::kClamp, &context, pose, {}}.Run();
      std::span<double> per_joint(errors.data() + f * joints, joints);
      ReferenceWorld(reference, f, local, world);
      meter.MeasureWorld(world, pose, per_joint);
      for (size_t j = 0; j < joints; ++j)
        if (!(per_joint[j] <= out.bound.precision)) {  // NaN too
          over.push_back(j);
          late = late || f + kSegmentFrames / 4 >= end;
        }
    }
    return over;
  }

  // Per joint, how much to tighten its tracks in `segment`: each joint over
  // the bound asks its chain for the share its worst frame is over, with a
  // margin, within [kTighten, kTightenLeast]; a track takes the least asked.
  std::vector<double> ChainFactors(size_t segment) const {
    const size_t n = joints, start = segment * kSegmentFrames;
    const size_t end = segment + 1 == segments ? out.frames.count : start + kSegmentFrames;
    std::vector<double> worst(n, 0.0), factors(n, 1.0);
    for (size_t f = start; f < end; ++f)
      for (size_t j = 0; j < n; ++j) worst[j] = std::max(worst[j], errors[f * n + j]);
    for (size_t j = 0; j < n; ++j) {
      if (worst[j] <= out.bound.precision) continue;
      const double factor = std::clamp(kTightenMargin * out.bound.precision / worst[j], kTighten, kTightenLeast);
      for (int k = static_cast<int>(j); k >= 0; k = skeleton.parents[k]) factors[k] = std::min(factors[k], factor);
    }
    return factors;
  }

  bool ChooseOrExplain(size_t segment) {
    if (segment < packed.size()) packed[segment].clear();
    if (Choose(states, out, segment)) return true;
    why = "a track cannot meet the bound at " + std::to_string(kMaxBits) + " bits";
    return false;
  }

  // Until every frame of `dirty` is within the bound: tighten the chains
  // over it. A segment chosen again changes its first samples, so the one
  // before it (which ends on them) is chosen again after it.
  bool MeetBound(std::vector<size_t> dirty) {
    std::vector<int> overs(segments, 0);  // rounds each segment was over
    for (int round = 0; round <= kRefinements; ++round) {
      Pack(states, packed, out);
      context.Resize(out);  // the packed bytes changed: no index of the old ones is kept
      std::vector<size_t> next;
      for (size_t s : dirty) {
        bool late = false;
        const std::vector<size_t> over = MeasureSegment(s, late);
        if (over.empty()) continue;
        if (round == kRefinements) {
          why = "the bound is not met after " + std::to_string(kRefinements) + " refinements";
          return false;
        }
        // The next segment's first samples are this one's last frame: tightened
        // too when a frame near it is over, or when this segment is over again.
        const std::vector<double> factors = ChainFactors(s);
        const size_t last = late || overs[s]++ > 0 ? std::min(s + 1, segments - 1) : s;
        for (size_t k = s; k <= last; ++k) {
          Tighten(states, factors, k);
          next.push_back(k);
        }
        if (s > 0) next.push_back(s - 1);
      }
      if (next.empty()) return true;
      SortDescendingUnique(next);
      for (size_t s : next)
        if (!ChooseOrExplain(s)) return false;
      // Each segment chosen again changed its first samples, which the one
      // before it ends on: that one is measured again too, even when it was
      // not chosen again (else its last frames could go over unseen).
      dirty = next;
      for (size_t s : next)
        if (s > 0) dirty.push_back(s - 1);
      SortDescendingUnique(dirty);
    }
    return true;
  }
};

// Orders the animated tracks for random access, once they are chosen: a
// seek reads the next segment's header as far as the last track whose
// interval ends on that segment's first sample, and a track of stride 2^k
// ends there at 2^k of a segment's 16 frames. The tracks that need it most
// often go first (the rest in joint order), so that walk is short. Each
// track decodes to the same values in any order. True when the order changed.
bool OrderForSeeks(std::vector<TrackState>& states, CompressedClip& out) {
  std::vector<size_t> weight(states.size(), 0), order(states.size());
  for (size_t t = 0; t < states.size(); ++t)
    for (const SegmentTrackChoice& c : states[t].choice) weight[t] += size_t{1} << kCodes[c.code].stride_log;
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return weight[a] > weight[b]; });
  if (std::is_sorted(order.begin(), order.end())) return false;
  std::vector<TrackState> ordered;
  ordered.reserve(states.size());
  for (size_t t = 0; t < order.size(); ++t) {
    ordered.push_back(std::move(states[order[t]]));
    out.animated[t] = ordered.back().track;
  }
  states = std::move(ordered);
  return true;
}

// The packed form keeps ranges and constants in float: a clip that moves
// or scales a joint past this magnitude is kept exact.
constexpr double kMaxPackedMagnitude = 1e30;

// The lossy form within the bound, or false (and a reason) when it cannot be met.
bool CompressLossy(const ClipReference& reference, CompressedClip& out, std::string& why) {
  if (const double largest = reference.largest_magnitude; !(largest < kMaxPackedMagnitude)) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", largest);
    why = std::string("a translation or scale of ") + text + " is past the packed form's float ranges";
    return false;
  }
  std::vector<TrackState> states;
  ClassifyTracks(reference, out.bound.precision, out, states);
  const size_t segments = SegmentCount(out.frames.count);
  for (const TrackState& s : states) out.animated.push_back(s.track);
  Refiner refiner(reference, out, states);
  std::vector<size_t> all;
  for (size_t s = segments; s-- > 0;) {  // last first: each segment ends on the next one's first samples
    if (!refiner.ChooseOrExplain(s)) {
      why = refiner.why;
      return false;
    }
    all.push_back(s);
  }
  if (segments == 0) {  // one frame: constants only
    Pack(states, refiner.packed, out);
    (void)ClipSamplingJob{&out, 0, WrapMode::kClamp, nullptr, refiner.pose, {}}.Run();
    ReferenceWorld(reference, 0, refiner.local, refiner.world);
    refiner.meter.MeasureWorld(refiner.world, refiner.pose, refiner.errors);
  } else if (!refiner.MeetBound(all)) {
    why = refiner.why;
    return false;
  }
  if (OrderForSeeks(states, out)) refiner.packed.clear();
  Pack(states, refiner.packed, out);
  out.error = SummarizeErrors(std::move(refiner.errors));
  if (!(out.error.worst <= out.bound.precision)) {  // NaN too
    why = "constant tracks exceed the bound";
    return false;
  }
  return true;
}

// Every morph weights track within WeightBound, or false (and a reason).
bool CompressMorphWeights(const Clip& clip, CompressedClip& out, std::string& why) {
  for (const WeightsTrack& track : clip.weights) {
    double worst = 0;
    std::optional<CompressedWeights> w = CompressWeights(track, out.frames, WeightBound(out.bound), worst);
    if (!w) {
      why = "the morph weights of " + track.mesh + " cannot meet the weight bound";
      return false;
    }
    out.weights.push_back(std::move(*w));
    out.weight_error = std::max(out.weight_error, worst);
  }
  return true;
}

}  // namespace

size_t CompressedClip::ByteSize() const {
  if (exact_keys) {
    size_t bytes = 0;
    for (const JointTrack& jt : exact_keys->joints)
      bytes += jt.rotation.times.size() * (sizeof(double) + sizeof(Eigen::Quaterniond)) +
               (jt.translation.times.size() + jt.scale.times.size()) * (sizeof(double) + sizeof(Eigen::Vector3d));
    return bytes;
  }
  size_t weight_bytes = 0;
  for (const CompressedWeights& w : weights) weight_bytes += w.ByteSize();
  return constants.size() * sizeof(ConstantTrack) + animated.size() * sizeof(AnimatedTrack) +
         segment_offsets.size() * sizeof(uint32_t) + data.size() + weight_bytes;
}

bool CompressedClip::SampleMorphWeights(std::string_view mesh, size_t targets, double time,
                                        const std::optional<Interpolation>& interpolation,
                                        std::span<double> out) const {
  if (exact_keys) {
    for (const WeightsTrack& track : exact_keys->weights) {
      if (track.mesh != mesh || track.targets != targets) continue;
      SampleWeights(track, time, {interpolation, WrapMode::kClamp}, out);
      return true;
    }
    return false;
  }
  for (const CompressedWeights& w : weights) {
    if (w.mesh != mesh || w.targets.size() != targets) continue;
    SampleCompressedWeights(w, frames, time, interpolation, out);
    return true;
  }
  return false;
}

double CompressedClip::BytesPerJointSample() const {
  const size_t samples = (skeleton ? skeleton->size() : 0) * frames.count;
  return samples ? static_cast<double>(ByteSize()) / static_cast<double>(samples) : 0;
}

std::optional<FrameGrid> CompressionFrames(const Clip& clip) {
  if (!(clip.duration > 0)) return FrameGrid{1, 0};
  // Counted in double: a long duration must not overflow the count before
  // the cap refuses it.
  const double own = static_cast<double>(clip.frame_count);
  const double least = std::ceil(clip.duration * kMinFramesPerSecond - 1e-9) + 1;
  double count = own;
  if (own < least) {
    // Each interval of the source's own split evenly, so that keys evenly spaced (a 24 fps glTF
    // clip) stay on frames; between frames the form interpolates, and a grid across the keys
    // would cut the corner at each one by far more than the bound.
    const double intervals = own > 1 ? own - 1 : 1;
    count = intervals * std::ceil((least - 1) / intervals) + 1;
    const double joints = static_cast<double>(std::max<size_t>(clip.skeleton->size(), 1));
    if (!(count * joints <= kMaxResampledJointSamples)) return std::nullopt;
  }
  const size_t frames = static_cast<size_t>(count);
  return FrameGrid{frames, clip.duration / static_cast<double>(frames - 1)};
}

StatusOr<std::shared_ptr<const CompressedClip>> CompressClip(std::shared_ptr<const Clip> clip,
                                                             const ClipPrecision& precision) {
  if (!clip) return Status::InvalidArgument("no clip to compress");
  ARMATURE_RETURN_IF_ERROR(CheckClipPrecision(precision));
  ARMATURE_RETURN_IF_ERROR(clip->Validate());
  ARMATURE_ASSIGN_OR_RETURN(const ErrorBound bound, ResolveErrorBound(*clip->skeleton, precision));
  static std::atomic<uint64_t> serials{0};
  auto out = std::make_shared<CompressedClip>();
  out->serial = ++serials;
  out->skeleton = clip->skeleton;
  out->duration = clip->duration;
  out->source_frame_time = clip->frame_time;
  out->source_frame_count = clip->frame_count;
  out->source_interpolation = clip->default_interpolation;
  const std::optional<FrameGrid> frames = CompressionFrames(*clip);
  // Over the cap: the source's own frames (the grid an exact clip lists).
  out->frames = frames.value_or(
      FrameGrid{clip->frame_count, clip->duration / static_cast<double>(std::max<size_t>(clip->frame_count, 2) - 1)});
  out->precision = precision;
  out->bound = bound;
  for (const JointTrack& jt : clip->joints)
    out->animated_parts.push_back(static_cast<uint8_t>((jt.rotation.empty() ? 0 : 1) |
                                                       (jt.translation.empty() ? 0 : 2) | (jt.scale.empty() ? 0 : 4)));
  if (!precision.exact) {
    std::string why;
    if (!frames) {
      char seconds[32];
      std::snprintf(seconds, sizeof seconds, "%g", clip->duration);
      why = "its " + std::to_string(clip->frame_count) + " frames over " + seconds +
            " s would be checked at 30 a second, over " +
            std::to_string(static_cast<uint64_t>(kMaxResampledJointSamples)) + " joint-samples";
    } else {
      ARMATURE_ASSIGN_OR_RETURN(const ClipReference reference,
                                SampleReference(*clip, out->frames, bound.shell_distance));
      if (CompressLossy(reference, *out, why) && CompressMorphWeights(*clip, *out, why))
        return std::shared_ptr<const CompressedClip>(std::move(out));
    }
    out->warning = "clip kept exact: " + why + " (" + std::to_string(precision.centimetres) + " cm)";
    out->constants.clear();
    out->animated.clear();
    out->segment_offsets.clear();
    out->data.clear();
    out->weights.clear();
    out->weight_error = 0;
    out->precision.exact = true;
  }
  out->exact_keys = clip;
  out->error = {};
  return std::shared_ptr<const CompressedClip>(std::move(out));
}

}  // namespace armature
