#include "anim/compression/clip_reference.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace armature::compression_internal {

namespace {

// Every track the source has, in joint order, then rotation, translation,
// scale (the order the compressor classifies them in), with room for
// every frame.
std::vector<TrackValues> SourceTracks(const Clip& clip, size_t frames) {
  std::vector<TrackValues> tracks;
  for (size_t j = 0; j < clip.joints.size(); ++j) {
    const JointTrack& jt = clip.joints[j];
    const bool has[3] = {!jt.rotation.empty(), !jt.translation.empty(), !jt.scale.empty()};
    const TrackKind kinds[3] = {TrackKind::kRotation, TrackKind::kTranslation, TrackKind::kScale};
    for (int k = 0; k < 3; ++k) {
      if (!has[k]) continue;
      TrackValues& t = tracks.emplace_back();
      t.joint = static_cast<uint16_t>(j);
      t.kind = kinds[k];
      t.raw.resize(frames * 4);
    }
  }
  return tracks;
}

// Frame `f`'s values of every track, from its local poses.
void StoreFrame(std::span<const Trs> local, size_t f, std::vector<TrackValues>& tracks) {
  for (TrackValues& t : tracks) {
    const Trs& trs = local[t.joint];
    double* v = &t.raw[f * 4];
    if (t.kind == TrackKind::kRotation) {
      const Eigen::Vector4d q = trs.rotation.coeffs();  // x y z w
      for (int c = 0; c < 4; ++c) v[c] = q[c];
    } else {
      const Eigen::Vector3d& x = t.kind == TrackKind::kTranslation ? trs.translation : trs.scale;
      for (int c = 0; c < 3; ++c) v[c] = x[c];
      v[3] = 0;
    }
  }
}

// The largest translation or scale component of `local` in magnitude, or
// infinity for one that is not finite.
double LargestMagnitude(std::span<const Trs> local) {
  double largest = 0;
  for (const Trs& p : local)
    for (int c = 0; c < 3; ++c)
      for (const double v : {p.translation[c], p.scale[c]}) {
        if (!std::isfinite(v)) return std::numeric_limits<double>::infinity();
        largest = std::max(largest, std::abs(v));
      }
  return largest;
}

// Each track's levers, once every frame's reach is known. A rotation error
// turns the farthest point by its chord; a translation moves everything
// below by the parent's scale; a scale error stretches the reach relative
// to the scale.
void SetLevers(ClipReference& r) {
  const size_t n = r.skeleton->size(), segments = r.segment_reach.size() / std::max<size_t>(n, 1);
  for (TrackValues& t : r.tracks) {
    auto lever = [&](double reach) {
      return t.kind == TrackKind::kRotation      ? reach
             : t.kind == TrackKind::kTranslation ? r.parent_scale[t.joint]
                                                 : reach / std::max(r.min_scale[t.joint], 1e-6);
    };
    t.lever = lever(r.reach[t.joint]);
    for (size_t s = 0; s < segments; ++s) t.segment_lever.push_back(lever(r.segment_reach[s * n + t.joint]));
  }
}

}  // namespace

StatusOr<ClipReference> SampleReference(const Clip& clip, const FrameGrid& frames, double shell_distance) {
  const Skeleton& skeleton = *clip.skeleton;
  ClipReference r;
  r.frames = frames;
  r.skeleton = &skeleton;
  r.tracks = SourceTracks(clip, frames.count);
  const size_t n = skeleton.size();
  r.reach.assign(n, 0);
  r.parent_scale.assign(n, 1);
  r.min_scale.assign(n, 1);
  const size_t segments = SegmentCount(frames.count);
  r.segment_reach.assign(segments * n, 0);
  std::vector<double> reach(n);
  std::vector<Trs> local(n);
  std::vector<WorldQvv> world(n);
  for (size_t f = 0; f < frames.count; ++f) {
    ARMATURE_RETURN_IF_ERROR(SampleClip(clip, frames.Time(f), {}, local));
    StoreFrame(local, f, r.tracks);
    r.largest_magnitude = std::max(r.largest_magnitude, LargestMagnitude(local));
    ComposeWorldQvv(skeleton, local, world);
    for (size_t j = 0; j < n; ++j) reach[j] = shell_distance * world[j].scale.cwiseAbs().maxCoeff();
    for (size_t j = n; j-- > 0;) {  // children after parents: fold each into its parent
      const int p = skeleton.parents[j];
      r.reach[j] = std::max(r.reach[j], reach[j]);
      // The frame belongs to its segment, and ends the one before when on a boundary.
      if (segments > 0) {
        const size_t s = std::min(f / kSegmentFrames, segments - 1);
        r.segment_reach[s * n + j] = std::max(r.segment_reach[s * n + j], reach[j]);
        if (f % kSegmentFrames == 0 && s > 0 && f / kSegmentFrames == s)
          r.segment_reach[(s - 1) * n + j] = std::max(r.segment_reach[(s - 1) * n + j], reach[j]);
      }
      r.min_scale[j] = std::min(r.min_scale[j], local[j].scale.cwiseAbs().minCoeff());
      if (p < 0) continue;
      reach[p] = std::max(reach[p], (world[j].translation - world[p].translation).norm() + reach[j]);
      r.parent_scale[j] = std::max(r.parent_scale[j], world[p].scale.cwiseAbs().maxCoeff());
    }
  }
  SetLevers(r);
  return r;
}

void ReferenceWorld(const ClipReference& reference, size_t f, std::span<Trs> local, std::span<WorldQvv> world) {
  std::copy(reference.skeleton->rest.begin(), reference.skeleton->rest.end(), local.begin());
  for (const TrackValues& t : reference.tracks) {
    const double* v = &t.raw[f * 4];
    Trs& p = local[t.joint];
    switch (t.kind) {
      case TrackKind::kRotation: p.rotation.coeffs() = Eigen::Vector4d(v[0], v[1], v[2], v[3]); break;
      case TrackKind::kTranslation: p.translation = Eigen::Vector3d(v[0], v[1], v[2]); break;
      case TrackKind::kScale: p.scale = Eigen::Vector3d(v[0], v[1], v[2]); break;
    }
  }
  ComposeWorldQvv(*reference.skeleton, local, world);
}

double RotationChord(const double* raw, const double* q) {
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  const double dot = raw[0] * q[0] + raw[1] * q[1] + raw[2] * q[2] + raw[3] * q[3];
  const double sign = dot < 0 ? -1 : 1;
  double d2 = 0;
  for (int c = 0; c < 4; ++c) d2 += (raw[c] - sign * q[c] / norm) * (raw[c] - sign * q[c] / norm);
  const double half = 0.5 * std::sqrt(d2);  // sin(angle/4)
  return 4 * half * std::sqrt(std::max(0.0, 1 - half * half));
}

bool ConstantFits(const TrackValues& track, const float* value, double limit) {
  const size_t frames = track.raw.size() / 4;
  for (size_t f = 0; f < frames; ++f) {
    const double* raw = &track.raw[f * 4];
    double e = 0;
    if (track.kind == TrackKind::kRotation) {
      const double q[4] = {value[0], value[1], value[2], value[3]};
      e = RotationChord(raw, q);
    } else {
      for (int c = 0; c < 3; ++c) e += (raw[c] - value[c]) * (raw[c] - value[c]);
      e = std::sqrt(e);
    }
    if (e * track.lever > limit) return false;
  }
  return true;
}

}  // namespace armature::compression_internal
