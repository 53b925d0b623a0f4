// Blendshapes (morph targets) on their own: M = M0 + Σ w_b·(M_b − M0), with
// the deltas stored sparsely. The skinning job applies the same deltas before
// skinning; this job evaluates them in the mesh's rest space only.
#pragma once

#include <span>
#include <string>

#include "armature/engine/mesh/mesh.h"
#include "armature/engine/mesh/skinning.h"
#include "armature/base/status.h"

namespace armature {

struct BlendshapeJob {
  const Mesh* mesh = nullptr;
  std::span<const float> weights;  // one per mesh target; empty = the mesh's default weights
  bool parallel = true;
  std::span<float> positions;  // out: x,y,z per vertex, rest space
  std::span<float> normals;    // out: empty, or x,y,z per vertex (renormalized); needs mesh normals
  SkinningWorkspace* workspace = nullptr;

  Status Validate() const;
  Status Run() const;  // validates first
};

// A sparse morph target from a full target shape M_b (x,y,z per vertex, the
// mesh's vertex order): keeps the vertices whose position (or normal) moves
// by more than `tolerance`. `normals` may be empty (no normal deltas).
StatusOr<MorphTarget> MorphTargetFromShape(const Mesh& base, std::string name, std::span<const float> positions,
                                           std::span<const float> normals = {}, float tolerance = 1e-6f);

}  // namespace armature
