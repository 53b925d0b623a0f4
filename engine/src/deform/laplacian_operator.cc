#include "armature/engine/deform/laplacian_operator.h"

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace armature {
namespace {

// A triangle whose doubled area is below this fraction of its longest edge
// squared has an angle near 0 or π: its cotangents blow up, so it is refused.
constexpr double kDegenerateAreaRatio = 1e-10;

std::string FormatVector(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

Eigen::SparseMatrix<double> UniformWeights(const MeshTopology& topo) {
  const auto n = static_cast<Eigen::Index>(topo.vertex_count);
  Eigen::VectorXi per_column(n);
  for (uint32_t v = 0; v < topo.vertex_count; ++v)
    per_column[v] = static_cast<int>(topo.neighbor_offsets[v + 1] - topo.neighbor_offsets[v]);
  Eigen::SparseMatrix<double> w(n, n);
  w.reserve(per_column);
  for (uint32_t v = 0; v < topo.vertex_count; ++v)
    for (uint32_t u : topo.Neighbors(v)) w.insert(u, v) = 1.0;
  w.makeCompressed();
  return w;
}

StatusOr<Eigen::SparseMatrix<double>> CotangentWeights(const Eigen::MatrixX3d& p, std::span<const uint32_t> triangles,
                                                       const MeshTopology& topo) {
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(triangles.size() * 2);
  for (size_t t = 0; t < topo.triangle_count; ++t) {
    const uint32_t* tri = &triangles[3 * t];
    const Eigen::Vector3d a = p.row(tri[0]), b = p.row(tri[1]), c = p.row(tri[2]);
    const double twice_area = (b - a).cross(c - a).norm();
    const double longest2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    if (!(twice_area > kDegenerateAreaRatio * longest2))
      return Status::InvalidArgument("triangles[" + std::to_string(t) + "] (vertices " + std::to_string(tri[0]) + ", " +
                                     std::to_string(tri[1]) + ", " + std::to_string(tri[2]) +
                                     ") is degenerate (zero area): cotangent weights need proper triangles; "
                                     "remove it or use uniform weights");
    for (int k = 0; k < 3; ++k) {
      // The angle at corner k weighs the edge opposite it: cot = u·v / |u×v|.
      const uint32_t i = tri[(k + 1) % 3], j = tri[(k + 2) % 3];
      const Eigen::Vector3d u = p.row(i) - p.row(tri[k]), v = p.row(j) - p.row(tri[k]);
      const double half_cot = 0.5 * u.dot(v) / twice_area;
      triplets.emplace_back(i, j, half_cot);
      triplets.emplace_back(j, i, half_cot);
    }
  }
  const auto n = static_cast<Eigen::Index>(topo.vertex_count);
  Eigen::SparseMatrix<double> w(n, n);
  w.setFromTriplets(triplets.begin(), triplets.end());
  w.makeCompressed();
  return w;
}

}  // namespace

std::string_view LaplacianWeightsName(LaplacianWeights w) {
  return w == LaplacianWeights::kCotangent ? "cotangent" : "uniform";
}

size_t LaplacianModel::memory_bytes() const {
  const auto sparse_bytes = [](const auto& m) {
    return static_cast<size_t>(m.nonZeros()) * (sizeof(double) + sizeof(int)) +
           static_cast<size_t>(m.outerSize() + 1) * sizeof(int);
  };
  return sizeof(*this) + topology.memory_bytes() - sizeof(topology) +
         static_cast<size_t>(rest_positions.size() + differential_coordinates.size()) * sizeof(double) +
         sparse_bytes(edge_weights) + sparse_bytes(laplacian);
}

StatusOr<std::shared_ptr<const LaplacianModel>> BuildLaplacianModel(const Eigen::MatrixX3d& positions,
                                                                    std::span<const uint32_t> triangles,
                                                                    const LaplacianModelOptions& options) {
  const size_t n = static_cast<size_t>(positions.rows());
  if (n == 0) return Status::InvalidArgument("the mesh has no vertices");
  if (n > options.max_vertices)
    return Status::ResourceExhausted("the mesh has " + std::to_string(n) + " vertices; the limit is " +
                                     std::to_string(options.max_vertices));
  if (triangles.empty()) return Status::InvalidArgument("the mesh has no triangles");
  if (n > static_cast<size_t>(INT32_MAX / 64))
    return Status::ResourceExhausted("the mesh has " + std::to_string(n) + " vertices, too many for 32-bit indices");
  for (size_t v = 0; v < n; ++v)
    if (!positions.row(static_cast<Eigen::Index>(v)).allFinite())
      return Status::InvalidArgument("vertex " + std::to_string(v) + " has a non-finite position " +
                                     FormatVector(positions.row(static_cast<Eigen::Index>(v))));

  ARMATURE_ASSIGN_OR_RETURN(auto topology, BuildMeshTopology(n, triangles));

  auto model = std::make_shared<LaplacianModel>();
  model->weights = options.weights;
  model->rest_positions = positions;
  model->topology = std::move(topology);
  if (options.weights == LaplacianWeights::kCotangent) {
    ARMATURE_ASSIGN_OR_RETURN(auto w, CotangentWeights(positions, triangles, model->topology));
    model->edge_weights = std::move(w);
  } else {
    model->edge_weights = UniformWeights(model->topology);
  }

  // L = I − D⁻¹W, row by row (W is symmetric, so its column v is row v).
  const auto& w = model->edge_weights;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<size_t>(w.nonZeros()) + n);
  for (Eigen::Index v = 0; v < w.outerSize(); ++v) {
    triplets.emplace_back(v, v, 1.0);
    if (model->topology.IsIsolated(static_cast<uint32_t>(v))) continue;
    double sum = 0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(w, v); it; ++it) sum += it.value();
    if (!(sum > 0))
      return Status::InvalidArgument("vertex " + std::to_string(v) + ": its " +
                                     std::string(LaplacianWeightsName(options.weights)) + " weights sum to " +
                                     std::to_string(sum) +
                                     " (obtuse triangles around it); L = I − D⁻¹W needs a positive sum, "
                                     "use uniform weights or remesh");
    for (Eigen::SparseMatrix<double>::InnerIterator it(w, v); it; ++it)
      triplets.emplace_back(v, it.index(), -it.value() / sum);
  }
  model->laplacian.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  model->laplacian.setFromTriplets(triplets.begin(), triplets.end());
  model->laplacian.makeCompressed();
  model->differential_coordinates = model->laplacian * positions;
  return std::shared_ptr<const LaplacianModel>(std::move(model));
}

StatusOr<std::shared_ptr<const LaplacianModel>> BuildLaplacianModel(std::span<const float> positions,
                                                                    std::span<const uint32_t> triangles,
                                                                    const LaplacianModelOptions& options) {
  if (positions.size() % 3 != 0)
    return Status::InvalidArgument("positions: expected 3 floats per vertex, got " + std::to_string(positions.size()));
  if (positions.size() / 3 > options.max_vertices)
    return Status::ResourceExhausted("the mesh has " + std::to_string(positions.size() / 3) +
                                     " vertices; the limit is " + std::to_string(options.max_vertices));
  const Eigen::MatrixX3d p = Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(
                                 positions.data(), static_cast<Eigen::Index>(positions.size() / 3), 3)
                                 .cast<double>();
  return BuildLaplacianModel(p, triangles, options);
}

}  // namespace armature
