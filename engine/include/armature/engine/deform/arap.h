// As-rigid-as-possible surface deformation (Sorkine & Alexa 2007). Laplacian
// editing keeps δ in its rest orientation, so rotating handles shears the
// detail; ARAP alternates a local step (each vertex's best rotation R_i from
// the SVD of its weighted edge covariance) and a global step (a solve with the
// matrix D − W, factored once per constraint set) to minimize
//   E = Σ_i Σ_{j∈N(i)} w_ij ‖(p′_i − p′_j) − R_i (p_i − p_j)‖².
// Weights w_ij are the model's (cotangent for the method as published).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <span>

#include "armature/engine/deform/deformation_constraints.h"
#include "armature/engine/deform/laplacian_operator.h"
#include "armature/engine/math/rotation.h"  // NearestRotation, the local step
#include "armature/base/status.h"

namespace armature {

struct ArapSolverOptions {
  size_t max_factorization_bytes = size_t{1} << 30;  // RESOURCE_EXHAUSTED above this
};

struct ArapOptions {
  int max_iterations = 10;  // local/global rounds; ≥ 1
  // Stop once no vertex moved more than tolerance × (rest bounding-box
  // diagonal) in a round.
  double tolerance = 1e-4;
  // true: `positions` holds the previous result and seeds the iteration (a
  // drag session converges in a round or two); false: start from the rest
  // shape with the handles moved, whose first round is a Laplacian solve.
  bool warm_start = false;
};

struct ArapReport {
  int iterations = 0;
  double last_change = 0;  // largest vertex move in the last round, relative to the bounding-box diagonal
  double energy = 0;       // E after the last global step, with that step's rotations
};

class ArapSolver {
 public:
  // Same validation as DeformationSolver::Create. The matrix is D − W over
  // the unknowns (plus w² on soft-constrained ones).
  static StatusOr<ArapSolver> Create(std::shared_ptr<const LaplacianModel> model,
                                     const DeformationConstraints& constraints, const ArapSolverOptions& options = {});

  ArapSolver(ArapSolver&&) noexcept;
  ArapSolver& operator=(ArapSolver&&) noexcept;
  ~ArapSolver();

  // `handle_positions`: x,y,z per handle; `positions`: x,y,z per vertex,
  // read as the initial guess under warm_start and written with the result.
  // Const and thread-safe; allocates its scratch once per call, not per round.
  StatusOr<ArapReport> Solve(std::span<const double> handle_positions, const ArapOptions& options,
                             std::span<double> positions) const;

  const LaplacianModel& model() const;
  size_t handle_count() const;
  size_t unknown_count() const;
  size_t factorization_bytes() const;
  size_t memory_bytes() const;

  struct Impl;  // opaque: keeps Eigen's solver types out of this header

 private:
  explicit ArapSolver(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace armature
