// The meshes the deformation benchmarks share: a 100k-vertex wavy sheet, as
// arrays (engine benchmarks) and as OBJ text (benchmarks that import it into
// a server).
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

#include "../tests/engine/generated_meshes.h"

namespace armature_bench {

inline constexpr int kSheetSide = 317;  // 100,489 vertices

// A kSheetSide² grid over [−1, 1]² with a small sine-cosine wave in z.
inline const armature::fixtures::GeneratedMesh& Sheet() {
  static const armature::fixtures::GeneratedMesh mesh = [] {
    armature::fixtures::GeneratedMesh m = armature::fixtures::MakeGrid(kSheetSide, kSheetSide, 2, 2);
    for (Eigen::Index v = 0; v < m.positions.rows(); ++v)
      m.positions(v, 2) = 0.05 * std::sin(20 * m.positions(v, 0)) * std::cos(15 * m.positions(v, 1));
    return m;
  }();
  return mesh;
}

// Sheet() as OBJ (positions printed to float precision, which is what a server stores).
inline std::string SheetObj() {
  const auto& m = Sheet();
  std::string obj;
  obj.reserve(static_cast<size_t>(m.positions.rows()) * 40 + m.triangles.size() * 10);
  char line[96];
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v) {
    std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", m.positions(v, 0), m.positions(v, 1), m.positions(v, 2));
    obj += line;
  }
  for (size_t k = 0; k < m.triangles.size(); k += 3) {
    std::snprintf(line, sizeof line, "f %u %u %u\n", m.triangles[k] + 1, m.triangles[k + 1] + 1, m.triangles[k + 2] + 1);
    obj += line;
  }
  return obj;
}

}  // namespace armature_bench
