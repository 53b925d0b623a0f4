// Internal: morph then skin (or copy) a mesh's vertices in chunks, shared by
// SkinningJob and BlendshapeJob.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Geometry>

#include "armature/engine/mesh/mesh.h"
#include "armature/engine/mesh/skinning.h"
#include "armature/base/status.h"

namespace armature::skinning_internal {

// Workspace arrays only ever grow, so a reused workspace stops allocating.
template <class T>
void Grow(std::vector<T>& v, size_t n) {
  if (v.size() < n) v.resize(n);
}

struct VertexPipeline {
  // skin = false: morph only, in rest space (BlendshapeJob).
  const Mesh* mesh;
  std::span<const Eigen::Affine3d> joint_world;
  std::span<const float> morph_weights;
  SkinningMethod method;
  bool skin;
  bool parallel;
  std::span<float> positions, normals;
  SkinningWorkspace* ws;
};

// Checks the mesh is finalized and the output spans and weights fit it.
Status CheckOutputs(const Mesh* mesh, std::span<const float> morph_weights, std::span<float> positions,
                    std::span<float> normals, const SkinningWorkspace* workspace);

Status RunVertexPipeline(const VertexPipeline& d);

}  // namespace armature::skinning_internal
