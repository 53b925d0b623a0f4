#include "polar.h"

#include <Eigen/LU>
#include <Eigen/SVD>

namespace armature {

void PolarDecompose(const Eigen::Matrix3d& l, Eigen::Matrix3d* rotation, Eigen::Matrix3d* stretch) {
  // L = U Σ Vᵀ = (U Vᵀ)(V Σ Vᵀ).
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(l, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  Eigen::Matrix3d sigma = svd.singularValues().asDiagonal();
  if ((u * svd.matrixV().transpose()).determinant() < 0) {
    u.col(2) = -u.col(2);
    sigma(2, 2) = -sigma(2, 2);
  }
  *rotation = u * svd.matrixV().transpose();
  if (stretch) *stretch = svd.matrixV() * sigma * svd.matrixV().transpose();
}

}  // namespace armature
