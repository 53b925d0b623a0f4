// Retargeting: a clip moved onto another skeleton whose joints have other
// names, frames, proportions and rest pose (T-pose or A-pose). In kinematics/
// because it needs world transforms (fk) and two-bone IK (feet); the joint map
// it takes is anim/body_part_map's.
//
// For each mapped pair the target's bone points where the source's bone
// points in world space. With Y the yaw that turns the source's facing onto
// the target's (from the thighs: left − right), Rs0/Rt0 the world rest
// rotations, Rs(t) the source's world rotation and C the rotation taking the
// target's rest bone (towards its mapped child) onto Y·(the source's rest
// bone):
//   Rt(t) = Y·Rs(t)·Rs0⁻¹·Y⁻¹ · C · Rt0,  local = parent_world⁻¹ · Rt(t)
// then turned by the swing that takes the bone onto the source's actual
// segment (exact when the source's segment spans several joints, CMU's
// Neck–Neck1–Head onto one neck bone). Unmapped target joints keep their rest
// pose. The root is translated so the target's hips (the thighs' midpoint) are
// at k·Y·(the source's), k = the ratio of leg lengths (thigh + shin), which
// also turns centimetres into metres. Up is +Y for both (BVH and glTF).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "armature/base/status.h"
#include "armature/engine/anim/clip.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/anim/body_part_map.h"
#include "armature/engine/anim/skeleton.h"

namespace armature {

struct RetargetOptions {
  // Pin the target's feet (two-bone IK per leg) where the source plants its
  // feet (low and slow). Needs a hip–knee–ankle chain per leg in the target.
  bool feet = false;
  // Seconds between output keys; 0 = the source's frame time, or 1/30 s for a
  // clip without one.
  double frame_time = 0.0;
  // RESOURCE_EXHAUSTED above either: frames, and keys (frames × animated joints)
  // so the output's memory is bounded (4M keys ≈ 128 MB).
  size_t max_frames = 200000;
  size_t max_keys = 4000000;
};

struct RetargetResult {
  Clip clip;           // on a copy of the target skeleton (joint names, order, rest)
  double scale = 1.0;  // k: target leg length / source leg length
  Eigen::Quaterniond yaw = Eigen::Quaterniond::Identity();  // Y
  size_t planted_frames = 0;                                // feet: frames (summed over both feet) pinned
  std::vector<std::string> warnings;
};

// The source is sampled through ClipSamplingJob (its runtime form; an exact
// one gives the stored keys). INVALID_ARGUMENT for pairs out of range or
// repeating a joint, or `feet` without a hip–knee–ankle chain in the target
// (naming the leg and the joint that breaks it).
StatusOr<RetargetResult> RetargetClip(const CompressedClip& source, const Skeleton& target, const BodyPartMap& map,
                                      const RetargetOptions& options = {});

}  // namespace armature
