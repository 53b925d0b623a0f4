// What a deformation is asked to do: which vertices the user drags
// (handles), which stay put (fixed), and where anything may move at all (the
// region of interest). One constraint set is one factorization: a drag only
// changes the handle *positions*, passed to Solve.
#pragma once

#include <cstdint>
#include <vector>

namespace armature {

enum class ConstraintMode {
  // Handles and fixed vertices are met exactly; they are eliminated from the
  // unknowns.
  kHard,
  // Handles and fixed vertices are pulled toward their targets with weight
  // `soft_weight`: least squares of [L; w·I_c]·V′ = [δ; w·U]. Vertices
  // outside the region of interest stay exactly put in both modes.
  kSoft,
};

struct DeformationConstraints {
  // Vertex indices moved by the caller; Solve takes one target position (x,y,z)
  // per entry, in this order. Unique, and not also in `fixed`.
  std::vector<uint32_t> handles;
  // Vertex indices held at their rest positions. Duplicates are harmless.
  std::vector<uint32_t> fixed;
  // When non-empty, only these vertices may move: every other vertex is held
  // at rest and the solve runs over the region alone (much faster for a local
  // edit on a large mesh). Handles must lie inside it.
  std::vector<uint32_t> region_of_interest;
  ConstraintMode mode = ConstraintMode::kHard;
  double soft_weight = 1.0;  // only for kSoft; finite and > 0
};

}  // namespace armature
