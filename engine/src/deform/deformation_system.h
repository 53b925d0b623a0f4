// Internal: what the Laplacian editor and ARAP share. A constraint set splits
// the vertices into unknowns and held vertices; both then solve a symmetric
// system over the unknowns alone, (M_uu + w²·S)·x_u = rhs, factored once.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "armature/engine/deform/deformation_constraints.h"
#include "armature/engine/deform/laplacian_operator.h"
#include "armature/base/status.h"

namespace armature::deformation_internal {

using SparseMatrix = Eigen::SparseMatrix<double>;
using PositionMap = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>;
using ConstPositionMap = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>;
using RowMatrixX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// How one constraint set splits the mesh. Hard mode solves for the free
// vertices; soft mode also for handles and fixed vertices (they get a w²
// pull). Vertices outside the region of interest, and vertices no triangle
// uses, are always held at rest.
struct VertexPartition {
  std::vector<int32_t> unknown_of_vertex;  // index into `unknowns`, or −1 when held
  std::vector<uint32_t> unknowns;          // vertices solved for, ascending
  std::vector<uint32_t> handles;           // the constraint set's handles, in order
  bool soft = false;
  double soft_weight_squared = 0;
  std::vector<uint32_t> soft_fixed;  // soft mode: unknown indices of fixed vertices (target: rest)

  size_t memory_bytes() const;
};

// Validates `constraints` against the mesh (INVALID_ARGUMENT naming the field,
// e.g. "handles[2].index 1200 is out of range (mesh has 1089 vertices)") and
// refuses a connected component with unknowns but no constraint, whose
// position the system cannot determine.
StatusOr<VertexPartition> PartitionVertices(const LaplacianModel& model, const DeformationConstraints& constraints);

// Rows of `rows` (r × n, vertex columns) split into the unknown columns
// (r × unknowns, renumbered) and the held columns (r × n, unknown columns empty).
struct SplitColumns {
  SparseMatrix unknown;
  SparseMatrix held;
};
SplitColumns SplitByUnknowns(const SparseMatrix& rows, const VertexPartition& partition);

// n × count selection matrix: column k picks vertex `vertices[k]`.
SparseMatrix VertexSelection(size_t n, std::span<const uint32_t> vertices);

// The factored reduced matrix M_uu + w²·S (S: ones on soft-constrained
// unknowns). Eigen's SimplicialLDLT with AMD ordering; SuiteSparse's CHOLMOD
// would drop in here if the build ever has it. Not movable (Eigen solvers
// are not): owners hold it in place.
class ReducedSystem {
 public:
  // Factors `m` (unknowns × unknowns, symmetric). RESOURCE_EXHAUSTED when the
  // factor would exceed `max_bytes` (checked after the symbolic analysis,
  // before the numeric factorization); INVALID_ARGUMENT when it is singular.
  Status Factor(SparseMatrix m, const VertexPartition& partition, size_t max_bytes);

  // M⁻¹·rhs for any number of columns (an expression: assigning it to a
  // sized matrix does not allocate).
  template <class Rhs>
  auto Solve(const Eigen::MatrixBase<Rhs>& rhs) const {
    return ldlt_.solve(rhs);
  }
  // x ← M⁻¹·x for the three coordinates at once, reading the factor once per
  // triangular pass (Eigen's solve goes column by column: three times the
  // memory traffic, and a drag or ARAP round is memory-bound). No allocation.
  void SolveInPlace(RowMatrixX3d& x) const;
  size_t factorization_bytes() const { return bytes_; }

 private:
  // Exposes the factor's size between analyzePattern() and factorize().
  class Ldlt : public Eigen::SimplicialLDLT<SparseMatrix> {
   public:
    Eigen::Index ReservedNonZeros() const { return m_matrix.nonZeros(); }
    const SparseMatrix& StrictLower() const { return m_matrix; }  // L without its unit diagonal
    const Eigen::VectorXd& Diagonal() const { return m_diag; }
  };
  Ldlt ldlt_;
  size_t bytes_ = 0;
};

// What every deformation solver holds: the shared model, how its constraint
// set splits the vertices, and the factored reduced matrix.
struct SolverCore {
  std::shared_ptr<const LaplacianModel> model;
  VertexPartition partition;
  ReducedSystem system;
};

// Checks the model and constraints and fills `core.model` and `core.partition`.
Status InitSolverCore(std::shared_ptr<const LaplacianModel> model, const DeformationConstraints& constraints,
                      SolverCore& core);

// Checks Solve's spans: 3 values per handle, 3 per vertex, all finite.
template <class T>
Status CheckSolveSpans(std::span<const T> handle_positions, size_t handle_count, size_t out_size, size_t vertex_count);

size_t SparseBytes(const SparseMatrix& m);

}  // namespace armature::deformation_internal
