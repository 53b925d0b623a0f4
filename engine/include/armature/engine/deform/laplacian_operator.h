// The Laplacian model of a triangle mesh: edge weights, the Laplace operator
// L and the differential coordinates δ = L·V of the rest shape. Immutable
// import-time data (Pinocchio's Model): built once per mesh and weighting,
// shared read-only by every deformation solver made from it.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>

#include "armature/engine/mesh/mesh_topology.h"
#include "armature/base/status.h"

namespace armature {

enum class LaplacianWeights {
  kUniform,    // w_ij = 1 for every edge: L = I − D⁻¹A (graph Laplacian; geometry-blind)
  kCotangent,  // w_ij = (cot α_ij + cot β_ij) / 2, the angles opposite edge ij
};

std::string_view LaplacianWeightsName(LaplacianWeights w);  // "uniform", "cotangent"

struct LaplacianModelOptions {
  LaplacianWeights weights = LaplacianWeights::kUniform;
  // Meshes above this size are refused with RESOURCE_EXHAUSTED before any
  // large allocation, so a server can bound its memory per request.
  size_t max_vertices = 2'000'000;
};

struct LaplacianModel {
  LaplacianWeights weights = LaplacianWeights::kUniform;
  Eigen::MatrixX3d rest_positions;  // V, one row per vertex
  MeshTopology topology;
  // W: symmetric edge weights, one entry (possibly 0) per mesh edge, none on
  // the diagonal. ARAP uses it directly (its system is D − W).
  Eigen::SparseMatrix<double> edge_weights;
  // L = I − D⁻¹W with D = diag(Σ_j w_ij): each row takes a vertex minus the
  // weighted average of its neighbours. A vertex no triangle uses has the row
  // e_i (it stays where it is).
  Eigen::SparseMatrix<double, Eigen::RowMajor> laplacian;
  Eigen::MatrixX3d differential_coordinates;  // δ = L·V

  size_t vertex_count() const { return static_cast<size_t>(rest_positions.rows()); }
  size_t memory_bytes() const;
};

// Builds the model from positions (one row, or 3 floats, per vertex) and
// triangles (3 indices each). INVALID_ARGUMENT names the problem: an empty
// mesh, a non-finite position ("vertex 5 has a non-finite position"), a bad
// index, and for cotangent weights a degenerate (zero-area) triangle or a
// vertex whose cotangent weights do not sum to a positive number.
// RESOURCE_EXHAUSTED when the mesh exceeds options.max_vertices.
StatusOr<std::shared_ptr<const LaplacianModel>> BuildLaplacianModel(const Eigen::MatrixX3d& positions,
                                                                    std::span<const uint32_t> triangles,
                                                                    const LaplacianModelOptions& options = {});
StatusOr<std::shared_ptr<const LaplacianModel>> BuildLaplacianModel(std::span<const float> positions,
                                                                    std::span<const uint32_t> triangles,
                                                                    const LaplacianModelOptions& options = {});

}  // namespace armature
