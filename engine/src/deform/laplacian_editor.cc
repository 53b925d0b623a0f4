#include "armature/engine/deform/laplacian_editor.h"

#include <string>
#include <utility>
#include <vector>

#include "deformation_system.h"
#include "parallel/worker_pool.h"

namespace armature {

using deformation_internal::SparseMatrix;

struct DeformationSolver::Impl : deformation_internal::SolverCore {
  // The right-hand side per unit handle displacement, B (unknowns × handles):
  // hard, −L_uᵀ·L_h (moving a handle column of L); soft, w² on the handle's row.
  SparseMatrix handle_rhs;
  // G = M⁻¹B (unknowns × handles), row-major so a drag streams it once; empty
  // under back-substitution.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> handle_basis;
};

namespace {

// Below about 1 MiB of basis a drag is a fraction of a millisecond: waking
// the workers would cost more than it saves.
constexpr size_t kParallelBasisEntries = size_t{1} << 17;

// The rows of L that touch an unknown: the unknowns and their neighbours.
// Every other row holds only held vertices, a constant the minimum ignores.
SparseMatrix RowsTouchingUnknowns(const LaplacianModel& model, const deformation_internal::VertexPartition& p) {
  const size_t n = model.vertex_count();
  std::vector<uint8_t> touches(n, 0);
  for (uint32_t v : p.unknowns) {
    touches[v] = 1;
    for (uint32_t u : model.topology.Neighbors(v)) touches[u] = 1;
  }
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::Index rows = 0;
  for (uint32_t v = 0; v < n; ++v) {
    if (!touches[v]) continue;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(model.laplacian, v); it; ++it)
      triplets.emplace_back(rows, it.col(), it.value());
    ++rows;
  }
  SparseMatrix l(rows, static_cast<Eigen::Index>(n));
  l.setFromTriplets(triplets.begin(), triplets.end());
  return l;
}

// `In` is the handles' type, `Out` the output's; the arithmetic is in double.
template <class In, class Out>
Status SolveInto(const DeformationSolver::Impl& s, std::span<const In> handle_positions, std::span<Out> out) {
  const LaplacianModel& model = *s.model;
  const auto& p = s.partition;
  const size_t n = model.vertex_count(), nh = p.handles.size();
  ARMATURE_RETURN_IF_ERROR(deformation_internal::CheckSolveSpans(handle_positions, nh, out.size(), n));
  Eigen::Map<Eigen::Matrix<Out, Eigen::Dynamic, 3, Eigen::RowMajor>> o(out.data(), static_cast<Eigen::Index>(n), 3);
  o = model.rest_positions.cast<Out>();
  if (nh > 0 && !p.unknowns.empty()) {
    // U − V_h, padded to 4 columns so the update below runs on whole SIMD packets.
    Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> shift =
        Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>::Zero(static_cast<Eigen::Index>(nh), 4);
    for (size_t k = 0; k < nh; ++k)
      shift.row(static_cast<Eigen::Index>(k)).head<3>() =
          Eigen::Map<const Eigen::Matrix<In, 1, 3>>(&handle_positions[3 * k]).template cast<double>() -
          model.rest_positions.row(p.handles[k]);
    if (s.handle_basis.size() > 0) {
      // V′_u = V_u + G·(U − V_h), one row of G at a time: G is read once, in
      // order. Streaming G is bound by memory, so large bases are split
      // across the cores: one core alone does not saturate the memory bus.
      const size_t nu = p.unknowns.size();
      auto rows = [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
          const double* g = s.handle_basis.data() + i * nh;
          Eigen::Vector4d d = Eigen::Vector4d::Zero();
          for (size_t k = 0; k < nh; ++k) d += g[k] * shift.row(static_cast<Eigen::Index>(k)).transpose();
          const uint32_t v = p.unknowns[i];
          o.row(v) = (model.rest_positions.row(v) + d.head<3>().transpose()).template cast<Out>();
        }
      };
      ParallelRanges(nu * nh >= kParallelBasisEntries ? &WorkerPool::Shared() : nullptr, nu, 4, rows);
    } else {
      deformation_internal::RowMatrixX3d displacement = s.handle_rhs * shift.leftCols<3>();
      s.system.SolveInPlace(displacement);
      for (size_t i = 0; i < p.unknowns.size(); ++i) {
        const uint32_t v = p.unknowns[i];
        o.row(v) = (model.rest_positions.row(v) + displacement.row(static_cast<Eigen::Index>(i))).template cast<Out>();
      }
    }
  }
  // Hard handles are not unknowns: they sit exactly where they were asked to.
  if (!p.soft)
    for (size_t k = 0; k < nh; ++k)
      o.row(p.handles[k]) = Eigen::Map<const Eigen::Matrix<In, 1, 3>>(&handle_positions[3 * k]).template cast<Out>();
  return Status::Ok();
}

}  // namespace

StatusOr<DeformationSolver> DeformationSolver::Create(std::shared_ptr<const LaplacianModel> model,
                                                      const DeformationConstraints& constraints,
                                                      const DeformationSolverOptions& options) {
  auto impl = std::make_unique<Impl>();
  ARMATURE_RETURN_IF_ERROR(deformation_internal::InitSolverCore(std::move(model), constraints, *impl));
  const auto& p = impl->partition;
  const size_t n = impl->model->vertex_count(), nu = p.unknowns.size(), nh = p.handles.size();

  // Normal equations of min ‖L_R(V′ − V)‖² over the unknowns:
  // (L_uᵀL_u + w²S)·x_u = L_uᵀ(−L_held·(V′ − V)_held) + w²S·(target − V).
  const SparseMatrix rows = RowsTouchingUnknowns(*impl->model, p);
  const deformation_internal::SplitColumns split = deformation_internal::SplitByUnknowns(rows, p);
  const SparseMatrix lu_t = split.unknown.transpose();
  ARMATURE_RETURN_IF_ERROR(impl->system.Factor(lu_t * split.unknown, p, options.max_factorization_bytes));

  if (p.soft) {
    impl->handle_rhs.resize(static_cast<Eigen::Index>(nu), static_cast<Eigen::Index>(nh));
    impl->handle_rhs.reserve(Eigen::VectorXi::Ones(static_cast<Eigen::Index>(nh)));
    for (size_t k = 0; k < nh; ++k)
      impl->handle_rhs.insert(p.unknown_of_vertex[p.handles[k]], static_cast<Eigen::Index>(k)) = p.soft_weight_squared;
    impl->handle_rhs.makeCompressed();
  } else {
    impl->handle_rhs = -(lu_t * (split.held * deformation_internal::VertexSelection(n, p.handles)));
  }

  const size_t basis_bytes = nu * nh * sizeof(double);
  const bool want_basis = options.drag_update == DragUpdate::kHandleBasis ||
                          (options.drag_update == DragUpdate::kAuto && basis_bytes <= options.max_handle_basis_bytes);
  if (want_basis && nu > 0 && nh > 0) {
    if (basis_bytes > options.max_handle_basis_bytes)
      return Status::ResourceExhausted("the handle basis needs " + std::to_string(basis_bytes >> 20) + " MiB for " +
                                       std::to_string(nh) + " handles; the limit is " +
                                       std::to_string(options.max_handle_basis_bytes >> 20) +
                                       " MiB (use back-substitution or fewer handles)");
    impl->handle_basis = impl->system.Solve(Eigen::MatrixXd(impl->handle_rhs));
  }
  return DeformationSolver(std::move(impl));
}

DeformationSolver::DeformationSolver(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
DeformationSolver::DeformationSolver(DeformationSolver&&) noexcept = default;
DeformationSolver& DeformationSolver::operator=(DeformationSolver&&) noexcept = default;
DeformationSolver::~DeformationSolver() = default;

Status DeformationSolver::Solve(std::span<const double> handle_positions, std::span<double> out) const {
  return SolveInto(*impl_, handle_positions, out);
}
Status DeformationSolver::Solve(std::span<const float> handle_positions, std::span<float> out) const {
  return SolveInto(*impl_, handle_positions, out);
}

Status DeformationSolver::Solve(std::span<const double> handle_positions, std::span<float> out) const {
  return SolveInto(*impl_, handle_positions, out);
}

const LaplacianModel& DeformationSolver::model() const { return *impl_->model; }
size_t DeformationSolver::handle_count() const { return impl_->partition.handles.size(); }
size_t DeformationSolver::unknown_count() const { return impl_->partition.unknowns.size(); }
bool DeformationSolver::uses_handle_basis() const { return impl_->handle_basis.size() > 0; }
size_t DeformationSolver::factorization_bytes() const { return impl_->system.factorization_bytes(); }
size_t DeformationSolver::handle_basis_bytes() const {
  return static_cast<size_t>(impl_->handle_basis.size()) * sizeof(double);
}
size_t DeformationSolver::memory_bytes() const {
  return sizeof(Impl) + impl_->partition.memory_bytes() + factorization_bytes() + handle_basis_bytes() +
         deformation_internal::SparseBytes(impl_->handle_rhs);
}

StatusOr<Eigen::MatrixX3d> DeformLaplacian(std::shared_ptr<const LaplacianModel> model,
                                           const DeformationConstraints& constraints,
                                           std::span<const double> handle_positions, size_t max_factorization_bytes) {
  DeformationSolverOptions options;
  options.max_factorization_bytes = max_factorization_bytes;
  options.drag_update = DragUpdate::kBackSubstitution;
  ARMATURE_ASSIGN_OR_RETURN(auto solver, DeformationSolver::Create(std::move(model), constraints, options));
  std::vector<double> out(3 * solver.model().vertex_count());
  ARMATURE_RETURN_IF_ERROR(solver.Solve(handle_positions, out));
  return Eigen::MatrixX3d(
      deformation_internal::ConstPositionMap(out.data(), static_cast<Eigen::Index>(out.size() / 3), 3));
}

}  // namespace armature
