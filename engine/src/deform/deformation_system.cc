#include "deformation_system.h"

#include <cmath>
#include <new>
#include <string>

namespace armature::deformation_internal {
namespace {

enum class Role : uint8_t { kFree, kHandle, kFixed, kHeld };

std::string OutOfRange(const std::string& field, uint32_t v, size_t n) {
  return field + " " + std::to_string(v) + " is out of range (mesh has " + std::to_string(n) + " vertices)";
}

}  // namespace

size_t VertexPartition::memory_bytes() const {
  return sizeof(*this) + unknown_of_vertex.capacity() * sizeof(int32_t) +
         (unknowns.capacity() + handles.capacity() + soft_fixed.capacity()) * sizeof(uint32_t);
}

size_t SparseBytes(const SparseMatrix& m) {
  return static_cast<size_t>(m.nonZeros()) * (sizeof(double) + sizeof(int)) +
         static_cast<size_t>(m.outerSize() + 1) * sizeof(int);
}

StatusOr<VertexPartition> PartitionVertices(const LaplacianModel& model, const DeformationConstraints& c) {
  const size_t n = model.vertex_count();
  const MeshTopology& topo = model.topology;
  if (c.mode == ConstraintMode::kSoft && !(std::isfinite(c.soft_weight) && c.soft_weight > 0))
    return Status::InvalidArgument("soft_weight must be finite and > 0, got " + std::to_string(c.soft_weight));

  std::vector<Role> role(n, Role::kFree);
  std::vector<uint8_t> in_roi;
  if (!c.region_of_interest.empty()) {
    in_roi.assign(n, 0);
    for (size_t i = 0; i < c.region_of_interest.size(); ++i) {
      const uint32_t v = c.region_of_interest[i];
      if (v >= n) return Status::InvalidArgument(OutOfRange("region_of_interest[" + std::to_string(i) + "]", v, n));
      in_roi[v] = 1;
    }
  }
  std::vector<int32_t> handle_slot(n, -1);
  for (size_t k = 0; k < c.handles.size(); ++k) {
    const uint32_t v = c.handles[k];
    const std::string field = "handles[" + std::to_string(k) + "].index";
    if (v >= n) return Status::InvalidArgument(OutOfRange(field, v, n));
    if (handle_slot[v] >= 0)
      return Status::InvalidArgument(field + " " + std::to_string(v) + " repeats handles[" +
                                     std::to_string(handle_slot[v]) + "].index");
    if (!in_roi.empty() && !in_roi[v])
      return Status::InvalidArgument(field + " " + std::to_string(v) + " lies outside the region of interest");
    handle_slot[v] = static_cast<int32_t>(k);
    role[v] = Role::kHandle;
  }
  for (size_t i = 0; i < c.fixed.size(); ++i) {
    const uint32_t v = c.fixed[i];
    const std::string field = "fixed[" + std::to_string(i) + "]";
    if (v >= n) return Status::InvalidArgument(OutOfRange(field, v, n));
    if (role[v] == Role::kHandle)
      return Status::InvalidArgument("handles[" + std::to_string(handle_slot[v]) + "].index " + std::to_string(v) +
                                     " is also fixed (" + field + "); a vertex is either dragged or held");
    role[v] = Role::kFixed;
  }
  for (uint32_t v = 0; v < n; ++v)
    if (role[v] == Role::kFree && ((!in_roi.empty() && !in_roi[v]) || topo.IsIsolated(v))) role[v] = Role::kHeld;

  // A component with unknowns and not one constraint floats freely: L has the
  // constants in its kernel there, so the system is singular.
  std::vector<uint8_t> anchored(topo.component_count, 0);
  for (uint32_t v = 0; v < n; ++v)
    if (role[v] != Role::kFree) anchored[topo.component[v]] = 1;
  for (uint32_t v = 0; v < n; ++v) {
    const uint32_t comp = topo.component[v];
    if (anchored[comp]) continue;
    size_t size = 0;
    for (uint32_t u = v; u < n; ++u) size += topo.component[u] == comp;
    return Status::InvalidArgument(
        "connected component " + std::to_string(comp) + " (" + std::to_string(size) + " vertices, including vertex " +
        std::to_string(v) + ") has no handle or fixed vertex" +
        (in_roi.empty() ? std::string() : " and lies inside the region of interest") +
        ": its position is undetermined (singular system); add a handle or fixed vertex on it" +
        (in_roi.empty() ? std::string() : " or leave it out of the region of interest"));
  }

  VertexPartition p;
  p.soft = c.mode == ConstraintMode::kSoft;
  p.soft_weight_squared = p.soft ? c.soft_weight * c.soft_weight : 0.0;
  p.handles = c.handles;
  p.unknown_of_vertex.assign(n, -1);
  for (uint32_t v = 0; v < n; ++v) {
    const bool unknown = role[v] == Role::kFree || (p.soft && (role[v] == Role::kHandle || role[v] == Role::kFixed));
    if (!unknown) continue;
    p.unknown_of_vertex[v] = static_cast<int32_t>(p.unknowns.size());
    if (role[v] == Role::kFixed) p.soft_fixed.push_back(static_cast<uint32_t>(p.unknowns.size()));
    p.unknowns.push_back(v);
  }
  return p;
}

SplitColumns SplitByUnknowns(const SparseMatrix& rows, const VertexPartition& partition) {
  std::vector<Eigen::Triplet<double>> unknown, held;
  unknown.reserve(static_cast<size_t>(rows.nonZeros()));
  for (Eigen::Index col = 0; col < rows.outerSize(); ++col) {
    const int32_t u = partition.unknown_of_vertex[static_cast<size_t>(col)];
    for (SparseMatrix::InnerIterator it(rows, col); it; ++it) {
      if (u >= 0)
        unknown.emplace_back(it.row(), u, it.value());
      else
        held.emplace_back(it.row(), col, it.value());
    }
  }
  SplitColumns s;
  s.unknown.resize(rows.rows(), static_cast<Eigen::Index>(partition.unknowns.size()));
  s.unknown.setFromTriplets(unknown.begin(), unknown.end());
  s.held.resize(rows.rows(), rows.cols());
  s.held.setFromTriplets(held.begin(), held.end());
  return s;
}

SparseMatrix VertexSelection(size_t n, std::span<const uint32_t> vertices) {
  SparseMatrix s(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(vertices.size()));
  s.reserve(Eigen::VectorXi::Ones(static_cast<Eigen::Index>(vertices.size())));
  for (size_t k = 0; k < vertices.size(); ++k) s.insert(vertices[k], static_cast<Eigen::Index>(k)) = 1.0;
  s.makeCompressed();
  return s;
}

Status ReducedSystem::Factor(SparseMatrix m, const VertexPartition& partition, size_t max_bytes) {
  if (partition.soft) {
    for (uint32_t k = 0; k < partition.handles.size(); ++k)
      m.coeffRef(partition.unknown_of_vertex[partition.handles[k]],
                 partition.unknown_of_vertex[partition.handles[k]]) += partition.soft_weight_squared;
    for (uint32_t u : partition.soft_fixed) m.coeffRef(u, u) += partition.soft_weight_squared;
  }
  m.makeCompressed();
  if (m.rows() == 0) return Status::Ok();  // everything is held: nothing to solve for
  try {
    ldlt_.analyzePattern(m);
    const size_t n = static_cast<size_t>(m.rows());
    // L's indices and values, D, the two permutations and the column counts.
    bytes_ = static_cast<size_t>(ldlt_.ReservedNonZeros()) * (sizeof(double) + sizeof(int)) +
             n * (sizeof(double) + 5 * sizeof(int));
    if (bytes_ > max_bytes)
      return Status::ResourceExhausted("the factorization needs " + std::to_string(bytes_ >> 20) +
                                       " MiB; the limit is " + std::to_string(max_bytes >> 20) +
                                       " MiB (shrink the region of interest)");
    ldlt_.factorize(m);
  } catch (const std::bad_alloc&) {
    return Status::ResourceExhausted("out of memory while factoring a " + std::to_string(m.rows()) + "-unknown system");
  }
  if (ldlt_.info() != Eigen::Success)
    return Status::InvalidArgument("the deformation system is singular (" + std::to_string(m.rows()) +
                                   " unknowns); check the weights and constraints");
  return Status::Ok();
}

Status InitSolverCore(std::shared_ptr<const LaplacianModel> model, const DeformationConstraints& constraints,
                      SolverCore& core) {
  if (!model) return Status::InvalidArgument("model is null");
  ARMATURE_ASSIGN_OR_RETURN(auto partition, PartitionVertices(*model, constraints));
  core.model = std::move(model);
  core.partition = std::move(partition);
  return Status::Ok();
}

void ReducedSystem::SolveInPlace(RowMatrixX3d& x) const {
  if (x.rows() == 0) return;
  // M = Pᵀ·L·D·Lᵀ·P, so x = Pᵀ·L⁻ᵀ·D⁻¹·L⁻¹·P·x; the permutations are applied in place.
  if (ldlt_.permutationP().size() > 0) x = ldlt_.permutationP() * x;
  const SparseMatrix& l = ldlt_.StrictLower();
  for (Eigen::Index j = 0; j < l.outerSize(); ++j) {
    const Eigen::RowVector3d xj = x.row(j);
    for (SparseMatrix::InnerIterator it(l, j); it; ++it) x.row(it.index()) -= it.value() * xj;
  }
  x.array().colwise() /= ldlt_.Diagonal().array();
  for (Eigen::Index j = l.outerSize() - 1; j >= 0; --j) {
    Eigen::RowVector3d xj = x.row(j);
    for (SparseMatrix::InnerIterator it(l, j); it; ++it) xj -= it.value() * x.row(it.index());
    x.row(j) = xj;
  }
  if (ldlt_.permutationPinv().size() > 0) x = ldlt_.permutationPinv() * x;
}

template <class T>
Status CheckSolveSpans(std::span<const T> handle_positions, size_t handle_count, size_t out_size, size_t vertex_count) {
  if (handle_positions.size() != 3 * handle_count)
    return Status::InvalidArgument("handle_positions: expected 3 values per handle (" +
                                   std::to_string(3 * handle_count) + " for " + std::to_string(handle_count) +
                                   " handles), got " + std::to_string(handle_positions.size()));
  if (out_size != 3 * vertex_count)
    return Status::InvalidArgument("output: expected 3 values per vertex (" + std::to_string(3 * vertex_count) +
                                   "), got " + std::to_string(out_size));
  for (size_t i = 0; i < handle_positions.size(); ++i)
    if (!std::isfinite(handle_positions[i]))
      return Status::InvalidArgument("handles[" + std::to_string(i / 3) + "].position is not finite");
  return Status::Ok();
}

template Status CheckSolveSpans<double>(std::span<const double>, size_t, size_t, size_t);
template Status CheckSolveSpans<float>(std::span<const float>, size_t, size_t, size_t);

}  // namespace armature::deformation_internal
