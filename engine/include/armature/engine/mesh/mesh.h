// Meshes: rest geometry, the skin binding it to skeleton joints, and morph
// targets (blendshapes). A Mesh is immutable import-time data shared by every
// request; its `layout` is the runtime form the skinning and blendshape jobs
// read, built once by FinalizeMesh.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "armature/base/status.h"
#include "armature/engine/mesh/material.h"

namespace armature {

// A blendshape as sparse deltas from the rest mesh: M = M0 + Σ w_b·Δ_b.
struct MorphTarget {
  std::string name;
  std::vector<uint32_t> vertices;                // strictly increasing vertex indices it moves
  std::vector<Eigen::Vector3f> position_deltas;  // one per entry of `vertices`
  std::vector<Eigen::Vector3f> normal_deltas;    // empty, or one per entry of `vertices`
};

// The SIMD-friendly runtime form of a mesh (structure of arrays, float).
// Vertices are stored grouped by influence count so each group runs a
// fixed-count loop; `order` maps back to the mesh's vertex order, which is the
// order of every output.
struct SkinningLayout {
  struct Group {
    uint32_t begin = 0, end = 0;  // runtime vertex range
    uint32_t influences = 0;      // per vertex (zero-weight padded above 8 to a multiple of 4)
    size_t first = 0;             // offset of this group's first influence in joints/weights
  };
  struct Target {                    // a morph target in runtime vertex order
    std::vector<uint32_t> vertices;  // strictly increasing runtime indices
    std::vector<float> dx, dy, dz;   // position deltas
    std::vector<float> nx, ny, nz;   // normal deltas (empty when the target has none)
  };

  std::vector<uint32_t> order;    // runtime index → mesh vertex index
  std::vector<float> x, y, z;     // rest positions
  std::vector<float> nx, ny, nz;  // rest normals (empty when the mesh has none)
  std::vector<Group> groups;      // ascending influence count, covering [0, vertices)
  std::vector<uint16_t> joints;   // skin joint per influence, vertex-major within a group
  std::vector<float> weights;     // normalized, descending per vertex
  // Dual quaternion blending flips an influence whose rotation lies in the
  // other hemisphere from the vertex's heaviest one. That depends only on
  // the pair (heaviest joint, joint), so each influence names its pair and
  // the job flips once per pair per call instead of once per vertex.
  std::vector<uint32_t> pair_offsets;                // per influence: 8 × its index into `pairs` (float offset)
  std::vector<std::pair<uint16_t, uint16_t>> pairs;  // (heaviest joint, joint) of the vertex
  std::vector<Target> targets;
};

struct Mesh {
  std::string name;  // local name inside its file (glTF mesh name or index); weights tracks refer to it

  // Rest geometry in the mesh's bind space.
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;  // empty, or one per vertex
  std::vector<uint32_t> triangles;       // three vertex indices per triangle
  std::vector<Eigen::Vector2f> uvs;      // texture coordinates (glTF TEXCOORD_0): empty, or one per vertex
  // How it is drawn: groups cover the triangles in order, each with one of
  // `materials` (shared with the file's other meshes). Both empty: none given.
  std::vector<std::shared_ptr<const Material>> materials;
  std::vector<MaterialGroup> material_groups;

  // Skin. `joints[k]` is the skeleton joint of skin joint k and
  // `inverse_bind[k]` takes bind-space points into that joint's frame, so a
  // vertex's world position is Σ w·world(joints[k])·inverse_bind[k]·p. A mesh
  // with no joints is unbound (e.g. a fresh OBJ): it only deforms by morphs.
  std::vector<int> joints;
  std::vector<Eigen::Affine3d> inverse_bind;
  int skeleton_root = -1;  // the skin's declared root joint (glTF skin.skeleton), or -1
  // Influences of vertex v are [influence_offsets[v], influence_offsets[v+1])
  // (size vertices+1 when skinned, else empty); joint values index `joints`.
  std::vector<uint32_t> influence_offsets;
  std::vector<uint32_t> influence_joints;
  std::vector<float> influence_weights;

  std::vector<MorphTarget> targets;
  std::vector<float> default_weights;  // one per target

  SkinningLayout layout;  // derived by FinalizeMesh; do not edit by hand

  size_t vertex_count() const { return positions.size(); }
  size_t triangle_count() const { return triangles.size() / 3; }
  bool skinned() const { return !joints.empty(); }
  size_t max_influences() const;
  // influence_histogram()[k] = number of vertices with k influences.
  std::vector<size_t> influence_histogram() const;
};

// Validates a mesh (indices in range, finite values, sizes agree), then
// normalizes each vertex's influences (drops zero weights, sorts by weight,
// scales to sum 1) and builds `layout`. Weights that did not sum to 1 (beyond
// 1e-3) are reported in `warnings` (one line, counting them); a skinned vertex
// without any positive weight is INVALID_ARGUMENT. Errors name the field.
Status FinalizeMesh(Mesh& mesh, std::vector<std::string>* warnings = nullptr);

// Area-weighted vertex normals from the triangles (zero for unused vertices).
std::vector<Eigen::Vector3f> ComputeVertexNormals(const std::vector<Eigen::Vector3f>& positions,
                                                  const std::vector<uint32_t>& triangles);

}  // namespace armature
