// Vertex connectivity of a triangle mesh: who neighbours whom, and which
// connected piece each vertex belongs to. Built once from the index buffer;
// the Laplacian and ARAP solvers read it, and the components are how they
// detect an unconstrained (singular) piece before factorizing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "armature/base/status.h"

namespace armature {

struct MeshTopology {
  size_t vertex_count = 0;
  size_t triangle_count = 0;
  // Compressed rows: the neighbours of v are neighbors[neighbor_offsets[v] .. neighbor_offsets[v+1]),
  // sorted ascending and unique. Size vertex_count + 1.
  std::vector<uint32_t> neighbor_offsets;
  std::vector<uint32_t> neighbors;
  // Connected component of each vertex, numbered in order of each piece's
  // lowest vertex. A vertex no triangle uses is a component of its own.
  std::vector<uint32_t> component;
  uint32_t component_count = 0;

  std::span<const uint32_t> Neighbors(uint32_t v) const {
    return {neighbors.data() + neighbor_offsets[v], neighbors.data() + neighbor_offsets[v + 1]};
  }
  bool IsIsolated(uint32_t v) const { return neighbor_offsets[v] == neighbor_offsets[v + 1]; }
  size_t edge_count() const { return neighbors.size() / 2; }
  size_t memory_bytes() const;
};

// `triangles` holds 3 vertex indices per triangle. Errors (INVALID_ARGUMENT)
// name the triangle: an index out of range, a vertex repeated in a triangle,
// an index count that is not a multiple of 3.
StatusOr<MeshTopology> BuildMeshTopology(size_t vertex_count, std::span<const uint32_t> triangles);

}  // namespace armature
