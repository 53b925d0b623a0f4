// Forward kinematics: local joint transforms → world transforms, with a
// floating root (the root's local transform is its world placement).
#pragma once

#include <span>

#include <Eigen/Geometry>

#include "armature/engine/anim/skeleton.h"
#include "armature/base/status.h"
#include "armature/engine/math/transform.h"

namespace armature {

// world[i] = world[parent(i)] · local[i]. Spans are caller-owned, size = joints.
// On a CPU with AVX2, four joints' rotations at a time and a column per
// register; the matrices are bit for bit ComputeWorldScalar's.
void ComputeWorld(const Skeleton& skeleton, std::span<const Trs> local, std::span<Eigen::Affine3d> world);

// The same, joint by joint in scalar code: what runs without AVX2, and the
// reference the vector kernel is tested against.
void ComputeWorldScalar(const Skeleton& skeleton, std::span<const Trs> local, std::span<Eigen::Affine3d> world);

// Same, but also the world rotation of each joint as a quaternion (the
// product of local rotations; scale is ignored for it), likewise bit for bit
// the scalar overload's.
void ComputeWorld(const Skeleton& skeleton, std::span<const Trs> local, std::span<Eigen::Affine3d> world,
                  std::span<Eigen::Quaterniond> world_rotation);
void ComputeWorldScalar(const Skeleton& skeleton, std::span<const Trs> local, std::span<Eigen::Affine3d> world,
                        std::span<Eigen::Quaterniond> world_rotation);

// A local pose from the rest pose with rotations and translations a client
// supplies: `rotations` has 4 per joint (w,x,y,z); `translations` is empty
// (rest offsets), 3 (root translation only) or 3 per joint. Quaternions are
// normalized; zero-length, NaN or wrongly sized input is INVALID_ARGUMENT.
Status PoseFromArrays(const Skeleton& skeleton, std::span<const float> rotations, std::span<const float> translations,
                      std::span<Trs> out);

}  // namespace armature
