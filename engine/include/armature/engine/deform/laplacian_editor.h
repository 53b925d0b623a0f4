// Laplacian mesh editing (Sorkine et al.): move handle vertices and let the
// rest of the surface follow while keeping its differential coordinates
// δ = L·V, i.e. minimize ‖L(V′ − V)‖² under the constraints. One solver is
// one factorization for one constraint set; each drag afterwards is cheap.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <span>

#include "armature/engine/deform/deformation_constraints.h"
#include "armature/engine/deform/laplacian_operator.h"
#include "armature/base/status.h"

namespace armature {

// How Solve turns new handle positions into vertex positions. The result
// is affine in the handle positions: V′_u = V_u + G·(U − V_h), G = M⁻¹B.
enum class DragUpdate {
  // Handle basis when it fits in max_handle_basis_bytes, else back-substitution.
  kAuto,
  // Precompute G's columns once (one back-substitution per handle at Create);
  // a drag is then a dense (unknowns × handles)·(handles × 3) product.
  kHandleBasis,
  // Keep only the factorization; a drag is one back-substitution with 3
  // right-hand sides.
  kBackSubstitution,
};

struct DeformationSolverOptions {
  size_t max_factorization_bytes = size_t{1} << 30;  // RESOURCE_EXHAUSTED above this
  size_t max_handle_basis_bytes = size_t{64} << 20;  // G's budget under kAuto / kHandleBasis
  DragUpdate drag_update = DragUpdate::kAuto;
};

class DeformationSolver {
 public:
  // Validates the constraints (INVALID_ARGUMENT naming the field, e.g.
  // "handles[2].index 1200 is out of range (mesh has 1089 vertices)", or the
  // connected component left without any constraint), builds the reduced
  // normal equations over the unknowns and factors them.
  static StatusOr<DeformationSolver> Create(std::shared_ptr<const LaplacianModel> model,
                                            const DeformationConstraints& constraints,
                                            const DeformationSolverOptions& options = {});

  DeformationSolver(DeformationSolver&&) noexcept;
  DeformationSolver& operator=(DeformationSolver&&) noexcept;
  ~DeformationSolver();

  // `handle_positions`: x,y,z per handle in constraints.handles order.
  // `out`: x,y,z per vertex (caller-owned). Hard handles and fixed vertices
  // land exactly on their targets; vertices outside the region of interest
  // keep their rest positions. Const and thread-safe: one solver can serve
  // concurrent drags. Scratch: handles × 4 doubles under the handle basis,
  // unknowns × 3 under back-substitution.
  Status Solve(std::span<const double> handle_positions, std::span<double> out) const;
  Status Solve(std::span<const float> handle_positions, std::span<float> out) const;
  // Double handles, float output (what an API answer carries), no double copy in between.
  Status Solve(std::span<const double> handle_positions, std::span<float> out) const;

  const LaplacianModel& model() const;
  size_t handle_count() const;
  size_t unknown_count() const;  // vertices actually solved for
  bool uses_handle_basis() const;
  size_t factorization_bytes() const;  // the sparse LDLᵀ factor
  size_t handle_basis_bytes() const;   // G, 0 without it
  size_t memory_bytes() const;         // everything this solver holds beyond the shared model

  struct Impl;  // opaque: keeps Eigen's solver types out of this header

 private:
  explicit DeformationSolver(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// One-shot edit for a unary request: factor, back-substitute once, return
// the deformed positions (one row per vertex).
StatusOr<Eigen::MatrixX3d> DeformLaplacian(std::shared_ptr<const LaplacianModel> model,
                                           const DeformationConstraints& constraints,
                                           std::span<const double> handle_positions,
                                           size_t max_factorization_bytes = size_t{1} << 30);

}  // namespace armature
