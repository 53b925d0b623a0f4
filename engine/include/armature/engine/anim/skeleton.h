// The skeleton: an immutable model of joints shared by every request
// (Pinocchio's Model). Per-request state lives in caller-owned spans.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "armature/base/status.h"
#include "armature/engine/math/transform.h"

namespace armature {

// A BVH channel: what one column of MOTION data drives.
enum class Channel : unsigned char { kXposition, kYposition, kZposition, kXrotation, kYrotation, kZrotation };

bool IsRotationChannel(Channel c);
std::string_view ChannelName(Channel c);  // "Xrotation" …

struct Skeleton {
  std::vector<std::string> names;
  // parents[i] < i (parents before children); -1 for a root. Several roots are allowed.
  std::vector<int> parents;
  // Rest (bind) local transforms; for BVH the translation is the OFFSET.
  std::vector<Trs> rest;
  // BVH channel lists in file order; empty vectors for skeletons from other formats.
  std::vector<std::vector<Channel>> channels;
  // End Site offsets in the joint's frame, so bones can be drawn to their tips.
  std::vector<std::optional<Eigen::Vector3d>> end_sites;
  // Skeleton units per centimetre when the file says (a glTF Armature wrote
  // from a skeleton not in metres); 0: UnitsPerCentimetre's rule decides.
  double units_per_centimetre = 0;

  size_t size() const { return names.size(); }
  // Index of the joint named `name`, or -1.
  int Find(std::string_view name) const;
  // Checks sizes agree, parents precede children, names are unique and non-empty,
  // and transforms are finite.
  Status Validate() const;
};

}  // namespace armature
