// Internal: polar decomposition of a 3×3 linear map.
#pragma once

#include <Eigen/Core>

namespace armature {

// L = R·S with R a proper rotation and S symmetric (the stretch). A
// reflection is carried by S (its smallest axis negated), so R stays a
// rotation a quaternion can hold.
void PolarDecompose(const Eigen::Matrix3d& l, Eigen::Matrix3d* rotation, Eigen::Matrix3d* stretch);

}  // namespace armature
