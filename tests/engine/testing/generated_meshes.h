// Meshes the deformation tests and benchmarks make themselves: grids, a plane
// with a bump, a tube, and concatenations (several connected components).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

namespace armature::fixtures {

struct GeneratedMesh {
  Eigen::MatrixX3d positions;
  std::vector<uint32_t> triangles;
};

// nx × ny vertices on [−width/2, width/2] × [−height/2, height/2] at z = 0;
// vertex (i, j) is j·nx + i. Each cell is split along the same diagonal.
inline GeneratedMesh MakeGrid(int nx, int ny, double width, double height) {
  GeneratedMesh m;
  m.positions.resize(static_cast<Eigen::Index>(nx) * ny, 3);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      m.positions.row(j * nx + i) << -width / 2 + width * i / (nx - 1), -height / 2 + height * j / (ny - 1), 0.0;
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const uint32_t a = static_cast<uint32_t>(j * nx + i), b = a + 1, c = a + 1 + static_cast<uint32_t>(nx),
                     d = a + static_cast<uint32_t>(nx);
      m.triangles.insert(m.triangles.end(), {a, b, c, a, c, d});
    }
  return m;
}

// A Gaussian bump of `height` and width `sigma` centred at (cx, cy), added to z.
inline void AddBump(GeneratedMesh& m, double cx, double cy, double height, double sigma) {
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v) {
    const double dx = m.positions(v, 0) - cx, dy = m.positions(v, 1) - cy;
    m.positions(v, 2) += height * std::exp(-(dx * dx + dy * dy) / (sigma * sigma));
  }
}

// An open tube along +x from 0 to `length`: `rings` rings of `segments`
// vertices; vertex (ring r, segment s) is r·segments + s.
inline GeneratedMesh MakeTube(int rings, int segments, double radius, double length) {
  GeneratedMesh m;
  m.positions.resize(static_cast<Eigen::Index>(rings) * segments, 3);
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double angle = 2 * std::numbers::pi * s / segments;
      m.positions.row(r * segments + s) << length * r / (rings - 1), radius * std::cos(angle), radius * std::sin(angle);
    }
  for (int r = 0; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const auto at = [&](int rr, int ss) { return static_cast<uint32_t>(rr * segments + (ss % segments)); };
      m.triangles.insert(m.triangles.end(),
                         {at(r, s), at(r + 1, s), at(r + 1, s + 1), at(r, s), at(r + 1, s + 1), at(r, s + 1)});
    }
  return m;
}

// `b` appended after `a`, with b's vertices shifted by `offset`: two components.
inline GeneratedMesh Concatenate(const GeneratedMesh& a, const GeneratedMesh& b, const Eigen::Vector3d& offset) {
  GeneratedMesh m;
  m.positions.resize(a.positions.rows() + b.positions.rows(), 3);
  m.positions << a.positions, b.positions.rowwise() + offset.transpose();
  m.triangles = a.triangles;
  for (uint32_t v : b.triangles) m.triangles.push_back(v + static_cast<uint32_t>(a.positions.rows()));
  return m;
}

// The mesh as OBJ text (v and f lines, positions to 9 significant digits),
// for tests and benchmarks that import it into the server.
inline std::string ToObj(const GeneratedMesh& m) {
  std::string obj;
  obj.reserve(static_cast<size_t>(m.positions.rows()) * 40 + m.triangles.size() * 10);
  char line[96];
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v) {
    std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", m.positions(v, 0), m.positions(v, 1), m.positions(v, 2));
    obj += line;
  }
  for (size_t t = 0; t + 2 < m.triangles.size(); t += 3) {
    std::snprintf(line, sizeof line, "f %u %u %u\n", m.triangles[t] + 1, m.triangles[t + 1] + 1,
                  m.triangles[t + 2] + 1);
    obj += line;
  }
  return obj;
}

}  // namespace armature::fixtures
