#include "anim/compression/clip_reference.h"

#include <algorithm>
#include <cmath>

namespace armature::compression_internal {

StatusOr<ClipReference> SampleReference(const Clip& clip, const FrameGrid& frames, double shell_distance) {
  const Skeleton& skeleton = *clip.skeleton;
  ClipReference r;
  r.frames = frames;
  r.joints = skeleton.size();
  const size_t n = r.joints;
  r.local.resize(frames.count * n);
  r.world.resize(frames.count * n);
  r.reach.assign(n, 0);
  r.parent_scale.assign(n, 1);
  r.min_scale.assign(n, 1);
  const size_t segments = SegmentCount(frames.count);
  r.segment_reach.assign(segments * n, 0);
  std::vector<double> reach(n);
  for (size_t f = 0; f < frames.count; ++f) {
    const std::span<Trs> local(r.local.data() + f * n, n);
    const std::span<WorldQvv> world(r.world.data() + f * n, n);
    ARMATURE_RETURN_IF_ERROR(SampleClip(clip, frames.Time(f), {}, local));
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
  return r;
}

TrackValues ReadTrack(const ClipReference& reference, uint16_t joint, TrackKind kind) {
  TrackValues t;
  t.joint = joint;
  t.kind = kind;
  const size_t n = reference.joints;
  t.raw.resize(reference.frames.count * 4);
  for (size_t f = 0; f < reference.frames.count; ++f) {
    const Trs& trs = reference.local[f * n + joint];
    double* v = &t.raw[f * 4];
    if (kind == TrackKind::kRotation) {
      const Eigen::Vector4d q = trs.rotation.coeffs();  // x y z w
      for (int c = 0; c < 4; ++c) v[c] = q[c];
    } else {
      const Eigen::Vector3d& x = kind == TrackKind::kTranslation ? trs.translation : trs.scale;
      for (int c = 0; c < 3; ++c) v[c] = x[c];
      v[3] = 0;
    }
  }
  // A rotation error turns the farthest point by its chord; a translation
  // moves everything below by the parent's scale; a scale error stretches
  // the reach relative to the scale.
  auto lever = [&](double reach) {
    return kind == TrackKind::kRotation      ? reach
           : kind == TrackKind::kTranslation ? reference.parent_scale[joint]
                                             : reach / std::max(reference.min_scale[joint], 1e-6);
  };
  t.lever = lever(reference.reach[joint]);
  const size_t segments = reference.segment_reach.size() / std::max<size_t>(n, 1);
  for (size_t s = 0; s < segments; ++s) t.segment_lever.push_back(lever(reference.segment_reach[s * n + joint]));
  return t;
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
