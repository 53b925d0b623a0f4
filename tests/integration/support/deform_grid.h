// The mesh the DeformService tests write themselves: a grid with a bump as
// OBJ, an edit on it (bottom row fixed, one top vertex dragged) and the unary
// request for that edit.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/testing/generated_meshes.h"
#include "armature/v1/deform.pb.h"

namespace armature::testing {

// An n×n grid over [0,1]² with a Gaussian bump of height `bump` in the middle.
// Positions are floats (what the server stores), printed so they read back exactly.
struct Grid {
  int n = 0;
  std::vector<float> positions;  // x,y,z per vertex
  fixtures::GeneratedMesh mesh;  // the same positions as doubles, and the triangles
  std::string obj;
  uint32_t at(int i, int j) const { return static_cast<uint32_t>(j * n + i); }
};

Grid MakeGrid(int n, float bump = 0.3f);

// The bottom row fixed, the top row's middle vertex dragged up and sideways.
struct Edit {
  std::vector<uint32_t> fixed, handles;
  std::vector<double> targets;
};

Edit BumpEdit(const Grid& g);

v1::DeformRequest RequestFor(const std::string& mesh, const Edit& e, v1::DeformWeights weights);

}  // namespace armature::testing
