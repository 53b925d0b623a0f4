#include "armature/engine/mesh/mesh_topology.h"

#include <algorithm>
#include <string>

namespace armature {

size_t MeshTopology::memory_bytes() const {
  return sizeof(*this) + (neighbor_offsets.capacity() + neighbors.capacity() + component.capacity()) * sizeof(uint32_t);
}

StatusOr<MeshTopology> BuildMeshTopology(size_t vertex_count, std::span<const uint32_t> triangles) {
  if (triangles.size() % 3 != 0)
    return Status::InvalidArgument("triangles: expected 3 indices per triangle, got " +
                                   std::to_string(triangles.size()) + " indices");
  MeshTopology topo;
  topo.vertex_count = vertex_count;
  topo.triangle_count = triangles.size() / 3;
  for (size_t t = 0; t < topo.triangle_count; ++t) {
    const uint32_t* tri = &triangles[3 * t];
    for (int k = 0; k < 3; ++k) {
      if (tri[k] >= vertex_count)
        return Status::InvalidArgument("triangles[" + std::to_string(t) + "] refers to vertex " +
                                       std::to_string(tri[k]) + ", which is out of range (mesh has " +
                                       std::to_string(vertex_count) + " vertices)");
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
      return Status::InvalidArgument("triangles[" + std::to_string(t) + "] repeats a vertex (" +
                                     std::to_string(tri[0]) + ", " + std::to_string(tri[1]) + ", " +
                                     std::to_string(tri[2]) + ")");
  }

  // Each triangle gives every corner its two other corners; counting sort by
  // vertex, then sort and deduplicate each vertex's run.
  std::vector<uint32_t> degree(vertex_count + 1, 0);
  for (uint32_t v : triangles) degree[v + 1] += 2;
  for (size_t v = 0; v < vertex_count; ++v) degree[v + 1] += degree[v];
  std::vector<uint32_t> raw(degree.back());
  std::vector<uint32_t> fill(degree.begin(), degree.end() - 1);
  for (size_t t = 0; t < topo.triangle_count; ++t) {
    const uint32_t* tri = &triangles[3 * t];
    for (int k = 0; k < 3; ++k) {
      raw[fill[tri[k]]++] = tri[(k + 1) % 3];
      raw[fill[tri[k]]++] = tri[(k + 2) % 3];
    }
  }
  topo.neighbor_offsets.assign(vertex_count + 1, 0);
  topo.neighbors.reserve(raw.size() / 2);
  for (size_t v = 0; v < vertex_count; ++v) {
    auto first = raw.begin() + degree[v], last = raw.begin() + degree[v + 1];
    std::sort(first, last);
    topo.neighbors.insert(topo.neighbors.end(), first, std::unique(first, last));
    topo.neighbor_offsets[v + 1] = static_cast<uint32_t>(topo.neighbors.size());
  }
  topo.neighbors.shrink_to_fit();

  // Components by breadth-first search from each unvisited vertex in order.
  constexpr uint32_t kUnvisited = UINT32_MAX;
  topo.component.assign(vertex_count, kUnvisited);
  std::vector<uint32_t> queue;
  queue.reserve(vertex_count);
  for (uint32_t seed = 0; seed < vertex_count; ++seed) {
    if (topo.component[seed] != kUnvisited) continue;
    const uint32_t id = topo.component_count++;
    topo.component[seed] = id;
    queue.assign(1, seed);
    for (size_t head = 0; head < queue.size(); ++head) {
      for (uint32_t n : topo.Neighbors(queue[head])) {
        if (topo.component[n] == kUnvisited) {
          topo.component[n] = id;
          queue.push_back(n);
        }
      }
    }
  }
  return topo;
}

}  // namespace armature
