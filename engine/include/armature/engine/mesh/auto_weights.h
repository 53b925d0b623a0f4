// Binding a rest mesh to a skeleton with automatically computed skin weights
// (e.g. an OBJ character to a BVH skeleton).
#pragma once

#include <string>
#include <vector>

#include "armature/engine/mesh/mesh.h"
#include "armature/engine/anim/skeleton.h"
#include "armature/base/status.h"

namespace armature {

enum class WeightMethod {
  // Inverse distance to each joint's bones with a smooth falloff.
  kDistance,
  // Baran & Popović's bone heat: solve (−Δ + H)·w_j = H·p_j on the surface
  // (cotangent Laplacian, H_ii = c/d_i² for the vertex's nearest visible bone).
  kHeat,
};

struct BindOptions {
  WeightMethod method = WeightMethod::kHeat;
  int max_influences = 4;    // keep at most this many joints per vertex, renormalized
  double falloff = 4;        // kDistance: weight ∝ 1/d^falloff
  double heat = 1;           // kHeat: c in H_ii = c/d_i²
  double min_weight = 1e-3;  // drop smaller weights (before renormalizing)
};

struct BindResult {
  Mesh mesh;  // skinned copy of the rest mesh, finalized
  std::vector<std::string> warnings;
};

// Binds `rest` (unbound, positioned in the skeleton's rest world space) to
// every joint of `skeleton`: joint j's bones are the segments from it to its
// children and its end site (a leaf without one is a point), inverse bind
// matrices are the inverses of the joints' rest world transforms. kHeat needs
// triangles; visibility is approximated by requiring the bone to lie behind
// the vertex's surface (against its normal), so a bone across a gap (the
// other leg, the torso from an arm) does not claim the vertex.
StatusOr<BindResult> BindMesh(const Mesh& rest, const Skeleton& skeleton, const BindOptions& options);

}  // namespace armature
