#include "armature/engine/deform/arap.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "armature/engine/math/rotation.h"
#include "deformation_system.h"

namespace armature {

using deformation_internal::SparseMatrix;

struct ArapSolver::Impl : deformation_internal::SolverCore {
  SparseMatrix held_coupling;  // (D − W) rows of the unknowns, held columns: moves held vertices to the rhs
  // Vertices whose rotation enters the global step: the unknowns and their
  // neighbours. rotation_slot maps a vertex to its index here (−1: none).
  std::vector<uint32_t> active;
  std::vector<int32_t> rotation_slot;
  double scale = 1;  // rest bounding-box diagonal
};

StatusOr<ArapSolver> ArapSolver::Create(std::shared_ptr<const LaplacianModel> model,
                                        const DeformationConstraints& constraints, const ArapSolverOptions& options) {
  auto impl = std::make_unique<Impl>();
  ARMATURE_RETURN_IF_ERROR(deformation_internal::InitSolverCore(std::move(model), constraints, *impl));
  const LaplacianModel& m = *impl->model;
  const auto& p = impl->partition;
  const size_t n = m.vertex_count();

  // Rows of D − W for the unknowns, columns in vertex numbering.
  std::vector<Eigen::Triplet<double>> triplets;
  for (size_t i = 0; i < p.unknowns.size(); ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    double sum = 0;
    for (SparseMatrix::InnerIterator it(m.edge_weights, p.unknowns[i]); it; ++it) {
      triplets.emplace_back(row, it.index(), -it.value());
      sum += it.value();
    }
    triplets.emplace_back(row, p.unknowns[i], sum);
  }
  SparseMatrix rows(static_cast<Eigen::Index>(p.unknowns.size()), static_cast<Eigen::Index>(n));
  rows.setFromTriplets(triplets.begin(), triplets.end());
  deformation_internal::SplitColumns split = deformation_internal::SplitByUnknowns(rows, p);
  ARMATURE_RETURN_IF_ERROR(impl->system.Factor(std::move(split.unknown), p, options.max_factorization_bytes));
  impl->held_coupling = std::move(split.held);

  impl->rotation_slot.assign(n, -1);
  const auto activate = [&](uint32_t v) {
    if (impl->rotation_slot[v] >= 0) return;
    impl->rotation_slot[v] = static_cast<int32_t>(impl->active.size());
    impl->active.push_back(v);
  };
  for (uint32_t v : p.unknowns) {
    activate(v);
    for (uint32_t u : m.topology.Neighbors(v)) activate(u);
  }
  const double diagonal = (m.rest_positions.colwise().maxCoeff() - m.rest_positions.colwise().minCoeff()).norm();
  impl->scale = diagonal > 0 ? diagonal : 1.0;
  return ArapSolver(std::move(impl));
}

ArapSolver::ArapSolver(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ArapSolver::ArapSolver(ArapSolver&&) noexcept = default;
ArapSolver& ArapSolver::operator=(ArapSolver&&) noexcept = default;
ArapSolver::~ArapSolver() = default;

StatusOr<ArapReport> ArapSolver::Solve(std::span<const double> handle_positions, const ArapOptions& options,
                                       std::span<double> positions) const {
  const Impl& s = *impl_;
  const LaplacianModel& m = *s.model;
  const auto& p = s.partition;
  const auto& w = m.edge_weights;
  const auto& rest = m.rest_positions;
  const size_t n = m.vertex_count(), nu = p.unknowns.size(), nh = p.handles.size();
  ARMATURE_RETURN_IF_ERROR(deformation_internal::CheckSolveSpans(handle_positions, nh, positions.size(), n));
  if (options.max_iterations < 1)
    return Status::InvalidArgument("max_iterations must be at least 1, got " + std::to_string(options.max_iterations));
  if (!(options.tolerance >= 0) || !std::isfinite(options.tolerance))
    return Status::InvalidArgument("tolerance must be finite and ≥ 0");

  deformation_internal::PositionMap pos(positions.data(), static_cast<Eigen::Index>(n), 3);
  if (options.warm_start) {
    for (size_t v = 0; v < n; ++v)
      if (!pos.row(static_cast<Eigen::Index>(v)).allFinite())
        return Status::InvalidArgument("warm start: positions of vertex " + std::to_string(v) + " are not finite");
  } else {
    pos = rest;
  }
  const deformation_internal::ConstPositionMap targets(handle_positions.data(), static_cast<Eigen::Index>(nh), 3);
  for (size_t v = 0; v < n; ++v)
    if (p.unknown_of_vertex[v] < 0) pos.row(static_cast<Eigen::Index>(v)) = rest.row(static_cast<Eigen::Index>(v));
  for (size_t k = 0; k < nh; ++k)
    if (!p.soft || !options.warm_start) pos.row(p.handles[k]) = targets.row(static_cast<Eigen::Index>(k));

  ArapReport report;
  if (nu == 0) return report;

  // The rhs part that does not change between rounds: held vertices moved to
  // the right, and the soft pulls w²·target.
  Eigen::MatrixX3d constant_rhs = -(s.held_coupling * pos);
  if (p.soft) {
    for (size_t k = 0; k < nh; ++k)
      constant_rhs.row(p.unknown_of_vertex[p.handles[k]]) +=
          p.soft_weight_squared * targets.row(static_cast<Eigen::Index>(k));
    for (uint32_t u : p.soft_fixed) constant_rhs.row(u) += p.soft_weight_squared * rest.row(p.unknowns[u]);
  }

  std::vector<Eigen::Matrix3d> rotation(s.active.size());
  deformation_internal::RowMatrixX3d solution(static_cast<Eigen::Index>(nu), 3);
  for (int round = 0; round < options.max_iterations; ++round) {
    // Local step: each vertex's best rotation of its rest edges onto the current ones.
    for (size_t a = 0; a < s.active.size(); ++a) {
      const uint32_t i = s.active[a];
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      for (SparseMatrix::InnerIterator it(w, i); it; ++it) {
        const Eigen::Vector3d e = (rest.row(i) - rest.row(it.index())).transpose();
        const Eigen::Vector3d e_new = (pos.row(i) - pos.row(it.index())).transpose();
        covariance.noalias() += it.value() * e * e_new.transpose();
      }
      rotation[a] = NearestRotation(covariance);
    }
    // Global step: Σ_j w_ij (p′_i − p′_j) = Σ_j w_ij/2 (R_i + R_j)(p_i − p_j).
    for (size_t u = 0; u < nu; ++u) {
      const uint32_t i = p.unknowns[u];
      const Eigen::Matrix3d& ri = rotation[s.rotation_slot[i]];
      Eigen::Vector3d b = Eigen::Vector3d::Zero();
      for (SparseMatrix::InnerIterator it(w, i); it; ++it) {
        const Eigen::Vector3d e = (rest.row(i) - rest.row(it.index())).transpose();
        b.noalias() += 0.5 * it.value() * ((ri + rotation[s.rotation_slot[it.index()]]) * e);
      }
      solution.row(static_cast<Eigen::Index>(u)) = b.transpose() + constant_rhs.row(static_cast<Eigen::Index>(u));
    }
    s.system.SolveInPlace(solution);
    double change = 0;
    for (size_t u = 0; u < nu; ++u) {
      auto row = pos.row(p.unknowns[u]);
      change = std::max(change, (solution.row(static_cast<Eigen::Index>(u)) - row).norm());
      row = solution.row(static_cast<Eigen::Index>(u));
    }
    report.iterations = round + 1;
    report.last_change = change / s.scale;
    if (report.last_change <= options.tolerance) break;
  }

  for (size_t a = 0; a < s.active.size(); ++a) {
    const uint32_t i = s.active[a];
    for (SparseMatrix::InnerIterator it(w, i); it; ++it) {
      const Eigen::Vector3d e = (rest.row(i) - rest.row(it.index())).transpose();
      const Eigen::Vector3d e_new = (pos.row(i) - pos.row(it.index())).transpose();
      report.energy += it.value() * (e_new - rotation[a] * e).squaredNorm();
    }
  }
  return report;
}

const LaplacianModel& ArapSolver::model() const { return *impl_->model; }
size_t ArapSolver::handle_count() const { return impl_->partition.handles.size(); }
size_t ArapSolver::unknown_count() const { return impl_->partition.unknowns.size(); }
size_t ArapSolver::factorization_bytes() const { return impl_->system.factorization_bytes(); }
size_t ArapSolver::memory_bytes() const {
  return sizeof(Impl) + impl_->partition.memory_bytes() + factorization_bytes() +
         deformation_internal::SparseBytes(impl_->held_coupling) +
         (impl_->active.capacity() + impl_->rotation_slot.capacity()) * sizeof(uint32_t);
}

}  // namespace armature
