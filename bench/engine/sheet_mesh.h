// The ~100k-vertex mesh the deformation benchmarks share (engine and RPC):
// a 317 × 317 wavy sheet, its drag constraints and drag targets.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "../../tests/engine/testing/generated_meshes.h"
#include "armature/engine/deform/deformation_constraints.h"

namespace armature_bench {

inline constexpr int kSheetSide = 317;  // 100,489 vertices

inline const armature::fixtures::GeneratedMesh& Sheet() {
  static const armature::fixtures::GeneratedMesh mesh = [] {
    armature::fixtures::GeneratedMesh m = armature::fixtures::MakeGrid(kSheetSide, kSheetSide, 2, 2);
    for (Eigen::Index v = 0; v < m.positions.rows(); ++v)
      m.positions(v, 2) = 0.05 * std::sin(20 * m.positions(v, 0)) * std::cos(15 * m.positions(v, 1));
    return m;
  }();
  return mesh;
}

// Boundary fixed; a side × side patch of handles at the centre; optionally a
// disc-shaped region of interest of the given radius (in grid steps).
inline armature::DeformationConstraints SheetConstraints(int patch_side, int roi_radius = 0) {
  armature::DeformationConstraints c;
  const int centre = kSheetSide / 2;
  const int lo = centre - patch_side / 2;
  for (int j = 0; j < kSheetSide; ++j)
    for (int i = 0; i < kSheetSide; ++i) {
      const auto v = static_cast<uint32_t>(j * kSheetSide + i);
      if (i == 0 || j == 0 || i == kSheetSide - 1 || j == kSheetSide - 1) c.fixed.push_back(v);
      if (i >= lo && i < lo + patch_side && j >= lo && j < lo + patch_side) c.handles.push_back(v);
      if (roi_radius > 0 && (i - centre) * (i - centre) + (j - centre) * (j - centre) <= roi_radius * roi_radius)
        c.region_of_interest.push_back(v);
    }
  return c;
}

// Handle targets for drag number `step`: the patch lifted and slid a little
// more each frame, from the handles' rest positions.
inline std::vector<double> SheetDragTargets(const armature::DeformationConstraints& c, int step) {
  std::vector<double> t;
  t.reserve(3 * c.handles.size());
  const double s = 0.001 * (step % 100);
  for (uint32_t v : c.handles)
    for (int k = 0; k < 3; ++k) t.push_back(Sheet().positions(v, k) + (k == 2 ? 3 * s : s));
  return t;
}

}  // namespace armature_bench
