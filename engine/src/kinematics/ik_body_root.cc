#include "armature/engine/kinematics/ik_body_root.h"

#include <algorithm>

#include "armature/engine/anim/body_part_map.h"

namespace armature {
namespace {

// Whether a translation track moves: keys (or tangents) that differ from the first key.
bool Moves(const Vec3Track& track) {
  if (track.values.empty()) return false;
  const Eigen::Vector3d& first = track.values.front();
  const double tolerance = 1e-9 * std::max(1.0, first.norm());
  for (const Eigen::Vector3d& v : track.values)
    if ((v - first).norm() > tolerance) return true;
  return false;
}

int LowestCommonAncestor(const Skeleton& skeleton, int a, int b) {
  std::vector<uint8_t> above_a(skeleton.size(), 0);
  for (int j = a; j >= 0; j = skeleton.parents[j]) above_a[j] = 1;
  for (int j = b; j >= 0; j = skeleton.parents[j])
    if (above_a[j]) return j;
  return -1;
}

}  // namespace

std::vector<uint8_t> BodyRootCandidates(const Skeleton& skeleton, std::span<const CompressedClip* const> clips) {
  std::vector<uint8_t> out(skeleton.size(), 0);
  for (const CompressedClip* clip : clips) {
    if (clip->exact()) {
      const Clip& keys = *clip->exact_keys;
      for (size_t j = 0; j < keys.joints.size() && j < out.size(); ++j)
        if (!out[j] && Moves(keys.joints[j].translation)) out[j] = 1;
      continue;
    }
    // Lossy: a translation that moves more than the bound has samples; one within it is kept constant.
    for (const AnimatedTrack& track : clip->animated)
      if (track.kind == TrackKind::kTranslation && track.joint < out.size()) out[track.joint] = 1;
  }
  const BodyParts parts = FindBodyParts(skeleton);
  const int left = parts.legs[0].upper, right = parts.legs[1].upper;
  if (left >= 0 && right >= 0 && skeleton.parents[left] >= 0 && skeleton.parents[right] >= 0) {
    const int parent = LowestCommonAncestor(skeleton, skeleton.parents[left], skeleton.parents[right]);
    if (parent >= 0) out[parent] = 1;
  }
  return out;
}

int BodyRootAbove(const Skeleton& skeleton, int joint, std::span<const uint8_t> candidates) {
  int top = joint;
  int found = -1;  // the candidate nearest the top seen so far, walking up
  for (int j = skeleton.parents[joint]; j >= 0; j = skeleton.parents[j]) {
    top = j;
    if (static_cast<size_t>(j) < candidates.size() && candidates[j]) found = j;
  }
  return found >= 0 ? found : top;
}

}  // namespace armature
