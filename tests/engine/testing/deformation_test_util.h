// Helpers shared by the Laplacian editor and ARAP tests.
#pragma once

#include <Eigen/Core>
#include <Eigen/SVD>
#include <cmath>
#include <cstdint>
#include <vector>

#include "armature/engine/mesh/mesh_topology.h"

namespace armature::fixtures {

// Row-per-vertex view of a solver's interleaved x,y,z output.
inline Eigen::MatrixX3d AsRows(const std::vector<double>& xyz) {
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      xyz.data(), static_cast<Eigen::Index>(xyz.size() / 3), 3);
}

// Interleaved x,y,z of the given rows (handle targets for Solve).
inline std::vector<double> Interleave(const Eigen::MatrixX3d& rows) {
  std::vector<double> out;
  for (Eigen::Index r = 0; r < rows.rows(); ++r)
    for (int k = 0; k < 3; ++k) out.push_back(rows(r, k));
  return out;
}

// Mean of |l′ − l| / l over the mesh edges.
inline double MeanEdgeLengthChange(const MeshTopology& topo, const Eigen::MatrixX3d& rest,
                                   const Eigen::MatrixX3d& deformed) {
  double sum = 0;
  size_t count = 0;
  for (uint32_t v = 0; v < topo.vertex_count; ++v)
    for (uint32_t u : topo.Neighbors(v)) {
      if (u < v) continue;
      const double l = (rest.row(v) - rest.row(u)).norm();
      sum += std::abs((deformed.row(v) - deformed.row(u)).norm() - l) / l;
      ++count;
    }
  return sum / static_cast<double>(count);
}

// RMS distance between `b` and the best rigid motion of `a` (Kabsch).
inline double RigidFitResidual(const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& b) {
  const Eigen::RowVector3d ca = a.colwise().mean(), cb = b.colwise().mean();
  const Eigen::MatrixX3d a0 = a.rowwise() - ca, b0 = b.rowwise() - cb;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(a0.transpose() * b0, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  const Eigen::Matrix3d r = svd.matrixV() * d * svd.matrixU().transpose();  // b0 ≈ a0·rᵀ
  return std::sqrt((a0 * r.transpose() - b0).squaredNorm() / static_cast<double>(a.rows()));
}

}  // namespace armature::fixtures
