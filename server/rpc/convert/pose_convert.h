// Poses, skeletons and sampling options ↔ API messages, shared by every slice.
// Asset listings convert in server/assets/asset_convert.h.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include <Eigen/Geometry>

#include "armature/engine/anim/clip.h"
#include "armature/engine/anim/skeleton.h"
#include <google/protobuf/repeated_field.h>

#include "armature/v1/types.pb.h"

namespace armature::server {

// A read-only view of a repeated scalar field, for engine functions taking spans.
template <class T>
std::span<const T> AsSpan(const google::protobuf::RepeatedField<T>& field) {
  return {field.data(), static_cast<size_t>(field.size())};
}

void ToProto(const Skeleton& skeleton, v1::Skeleton* out);

std::optional<Interpolation> FromProto(v1::Interpolation interpolation);  // UNSPECIFIED → the clip's own
v1::Interpolation ToProto(Interpolation interpolation);
WrapMode FromProto(v1::WrapMode wrap);

// Per-request scratch space for turning a sampled pose into a message.
struct PoseWorkspace {
  std::vector<Trs> local;
  std::vector<Eigen::Affine3d> world;
  std::vector<Eigen::Quaterniond> world_rotation;
  void Resize(size_t joints) {
    local.resize(joints);
    world.resize(joints);
    world_rotation.resize(joints);
  }
};

// Writes the joints listed in `joints` of the pose in `ws.local` into `out`:
// LOCAL gives local TRS (scales only when some differ from 1); WORLD gives
// world positions and rotations.
void PackPose(const Skeleton& skeleton, v1::Space space, std::span<const int> joints, PoseWorkspace& ws, v1::Pose* out);

}  // namespace armature::server
