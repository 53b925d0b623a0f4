// A joint's local transform as translation, rotation and scale (TRS), the
// decomposition both BVH and glTF use. Matrices are built from it, never
// interpolated directly.
#pragma once

#include <Eigen/Geometry>

namespace armature {

struct Trs {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();

  // M = T · R · S
  Eigen::Affine3d ToAffine() const {
    Eigen::Affine3d m = Eigen::Affine3d::Identity();
    m.linear() = rotation.toRotationMatrix() * scale.asDiagonal();
    m.translation() = translation;
    return m;
  }
};

// An affine matrix as T·R·S. Exact for matrices built from TRS (a negative
// determinant becomes a negative x scale); a matrix with shear or a zero
// scale keeps its nearest rotation and sets `*exact` false.
Trs DecomposeAffine(const Eigen::Matrix4d& m, bool* exact);

}  // namespace armature
