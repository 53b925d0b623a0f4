#include "deform_grid.h"

#include <cmath>

namespace armature::testing {

Grid MakeGrid(int n, float bump) {
  Grid g;
  g.n = n;
  g.mesh = fixtures::MakeGrid(n, n, 1.0, 1.0);  // for its triangles; the positions are the floats below
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float x = static_cast<float>(i) / static_cast<float>(n - 1),
                  y = static_cast<float>(j) / static_cast<float>(n - 1);
      const float z = bump * std::exp(-((x - 0.5f) * (x - 0.5f) + (y - 0.5f) * (y - 0.5f)) / 0.02f);
      g.positions.insert(g.positions.end(), {x, y, z});
      g.mesh.positions.row(g.at(i, j)) << x, y, z;
    }
  g.obj = fixtures::ToObj(g.mesh);
  return g;
}

Edit BumpEdit(const Grid& g) {
  Edit e;
  for (int i = 0; i < g.n; ++i) e.fixed.push_back(g.at(i, 0));
  const uint32_t h = g.at(g.n / 2, g.n - 1);
  e.handles = {h};
  e.targets = {g.positions[3 * h] + 0.1, g.positions[3 * h + 1] + 0.05, g.positions[3 * h + 2] + 0.4};
  return e;
}

v1::DeformRequest RequestFor(const std::string& mesh, const Edit& e, v1::DeformWeights weights) {
  v1::DeformRequest r;
  r.set_mesh(mesh);
  r.set_weights(weights);
  for (uint32_t v : e.fixed) r.add_fixed(v);
  for (size_t k = 0; k < e.handles.size(); ++k) {
    auto* h = r.add_handles();
    h->set_index(e.handles[k]);
    for (int a = 0; a < 3; ++a) h->add_position(e.targets[3 * k + a]);
  }
  return r;
}

}  // namespace armature::testing
