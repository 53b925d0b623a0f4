#include "armature/engine/math/transform.h"

#include "armature/engine/math/rotation.h"

namespace armature {

Trs DecomposeAffine(const Eigen::Matrix4d& m, bool* exact) {
  Trs trs;
  trs.translation = m.block<3, 1>(0, 3);
  const Eigen::Matrix3d l = m.topLeftCorner<3, 3>();
  Eigen::Vector3d scale = l.colwise().norm();
  if (l.determinant() < 0) scale.x() = -scale.x();
  Eigen::Matrix3d r = l;
  bool is_exact = scale.cwiseAbs().minCoeff() > 0;
  if (is_exact) {
    r = l * scale.cwiseInverse().asDiagonal();
    is_exact = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-5;
  }
  if (!is_exact) r = NearestRotation(l.transpose());  // the rotation of the polar decomposition L = R·S
  trs.rotation = Eigen::Quaterniond(r).normalized();
  trs.scale = scale;
  if (exact) *exact = is_exact;
  return trs;
}

}  // namespace armature
