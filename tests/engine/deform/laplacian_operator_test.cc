#include "armature/engine/deform/laplacian_operator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "armature/engine/mesh/mesh_topology.h"
#include "../testing/generated_meshes.h"

namespace armature {
namespace {

using fixtures::MakeGrid;

TEST(MeshTopology, GridNeighboursAndComponents) {
  // 3×3 grid, cells split along (i,j)–(i+1,j+1): the centre (4) touches all
  // but the two corners off its diagonals (2 and 6).
  const auto grid = MakeGrid(3, 3, 2, 2);
  auto topo = BuildMeshTopology(9, grid.triangles);
  ASSERT_TRUE(topo.ok()) << topo.status().message();
  const auto centre = topo->Neighbors(4);
  EXPECT_EQ(std::vector<uint32_t>(centre.begin(), centre.end()), (std::vector<uint32_t>{0, 1, 3, 5, 7, 8}));
  const auto corner = topo->Neighbors(2);
  EXPECT_EQ(std::vector<uint32_t>(corner.begin(), corner.end()), (std::vector<uint32_t>{1, 5}));
  EXPECT_EQ(topo->edge_count(), 16u);  // 12 cell sides + 4 diagonals
  EXPECT_EQ(topo->component_count, 1u);

  // Two grids plus an unused vertex: three components, numbered by lowest vertex.
  const auto two = fixtures::Concatenate(grid, grid, {5, 0, 0});
  auto topo2 = BuildMeshTopology(19, two.triangles);
  ASSERT_TRUE(topo2.ok());
  EXPECT_EQ(topo2->component_count, 3u);
  EXPECT_EQ(topo2->component[8], 0u);
  EXPECT_EQ(topo2->component[9], 1u);
  EXPECT_EQ(topo2->component[18], 2u);
  EXPECT_TRUE(topo2->IsIsolated(18));
}

TEST(MeshTopology, RejectsBadIndices) {
  const std::vector<uint32_t> out_of_range = {0, 1, 2, 0, 2, 7};
  auto st = BuildMeshTopology(4, out_of_range).status();
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message(), "triangles[1] refers to vertex 7, which is out of range (mesh has 4 vertices)");
  const std::vector<uint32_t> repeated = {0, 1, 1};
  st = BuildMeshTopology(4, repeated).status();
  EXPECT_NE(st.message().find("triangles[0] repeats a vertex"), std::string::npos) << st.message();
  const std::vector<uint32_t> ragged = {0, 1, 2, 3};
  EXPECT_EQ(BuildMeshTopology(4, ragged).status().code(), StatusCode::kInvalidArgument);
}

TEST(LaplacianOperator, UniformRowsAverageTheNeighbours) {
  const auto grid = MakeGrid(3, 3, 2, 2);
  auto model = BuildLaplacianModel(grid.positions, grid.triangles);
  ASSERT_TRUE(model.ok()) << model.status().message();
  const auto& l = (*model)->laplacian;
  // Centre: 6 neighbours, each −1/6; corner 2: neighbours 1 and 5, −1/2 each.
  EXPECT_DOUBLE_EQ(l.coeff(4, 4), 1.0);
  for (int j : {0, 1, 3, 5, 7, 8}) EXPECT_DOUBLE_EQ(l.coeff(4, j), -1.0 / 6);
  EXPECT_DOUBLE_EQ(l.coeff(4, 2), 0.0);
  EXPECT_DOUBLE_EQ(l.coeff(2, 1), -0.5);
  EXPECT_DOUBLE_EQ(l.coeff(2, 5), -0.5);
  // δ of the flat symmetric centre is 0; corner 2 = (1,−1) minus the mean of (0,−1), (1,0).
  const Eigen::MatrixX3d& delta = (*model)->differential_coordinates;
  EXPECT_NEAR(delta.row(4).norm(), 0.0, 1e-15);
  EXPECT_TRUE(delta.row(2).isApprox(Eigen::RowVector3d(0.5, -0.5, 0), 1e-15));
}

// Two right triangles whose angles are worked out by hand:
//   c(0,1) — d(2,1)
//   |  ╲      |
//   a(0,0) — b(2,0)     triangles (a,b,c) and (b,d,c).
// In abc: angle a = 90° (cot 0, opposite bc), b: cot = 2 (opposite ac),
// c: cot = 1/2 (opposite ab). In bdc: d = 90° (cot 0, opposite bc),
// b: cot = 1/2 (opposite cd), c: cot = 2 (opposite bd).
// w = (Σ cot)/2: ab 1/4, ac 1, bc 0, bd 1, cd 1/4.
TEST(LaplacianOperator, CotangentWeightsMatchHandDerivedValues) {
  Eigen::MatrixX3d p(4, 3);
  p << 0, 0, 0,  //
      2, 0, 0,   //
      0, 1, 0,   //
      2, 1, 0;
  const std::vector<uint32_t> tri = {0, 1, 2, 1, 3, 2};
  LaplacianModelOptions options;
  options.weights = LaplacianWeights::kCotangent;
  auto model = BuildLaplacianModel(p, tri, options);
  ASSERT_TRUE(model.ok()) << model.status().message();
  const auto& w = (*model)->edge_weights;
  EXPECT_NEAR(w.coeff(0, 1), 0.25, 1e-15);
  EXPECT_NEAR(w.coeff(0, 2), 1.0, 1e-15);
  EXPECT_NEAR(w.coeff(1, 2), 0.0, 1e-15);
  EXPECT_NEAR(w.coeff(1, 3), 1.0, 1e-15);
  EXPECT_NEAR(w.coeff(2, 3), 0.25, 1e-15);
  EXPECT_NEAR(w.coeff(3, 1), 1.0, 1e-15);  // symmetric
  // Row a: weights sum 1.25 → L_ab = −0.2, L_ac = −0.8; δ_a = a − 0.2b − 0.8c.
  const auto& l = (*model)->laplacian;
  EXPECT_NEAR(l.coeff(0, 1), -0.2, 1e-15);
  EXPECT_NEAR(l.coeff(0, 2), -0.8, 1e-15);
  EXPECT_NEAR(l.coeff(1, 3), -0.8, 1e-15);
  EXPECT_NEAR(l.coeff(1, 2), 0.0, 1e-15);
  EXPECT_TRUE((*model)->differential_coordinates.row(0).isApprox(Eigen::RowVector3d(-0.4, -0.8, 0), 1e-14));
}

// A regular tetrahedron: every angle is 60°, so every edge weighs
// (cot 60° + cot 60°)/2 = 1/√3 and δ_i = p_i − centroid of the other three.
TEST(LaplacianOperator, CotangentWeightsOfRegularTetrahedron) {
  Eigen::MatrixX3d p(4, 3);
  p << 1, 1, 1,   //
      1, -1, -1,  //
      -1, 1, -1,  //
      -1, -1, 1;
  const std::vector<uint32_t> tri = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
  LaplacianModelOptions options;
  options.weights = LaplacianWeights::kCotangent;
  auto model = BuildLaplacianModel(p, tri, options);
  ASSERT_TRUE(model.ok()) << model.status().message();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (i != j) EXPECT_NEAR((*model)->edge_weights.coeff(i, j), 1 / std::sqrt(3.0), 1e-14);
  // p_0 − mean(p_1, p_2, p_3) = (1,1,1) − (−1/3, −1/3, −1/3).
  EXPECT_TRUE((*model)->differential_coordinates.row(0).isApprox(Eigen::RowVector3d(4, 4, 4) / 3, 1e-14));
}

TEST(LaplacianOperator, FloatPositionsGiveTheSameModel) {
  const auto grid = MakeGrid(4, 3, 3, 2);
  std::vector<float> flat;
  for (Eigen::Index v = 0; v < grid.positions.rows(); ++v)
    for (int k = 0; k < 3; ++k) flat.push_back(static_cast<float>(grid.positions(v, k)));
  auto a = BuildLaplacianModel(grid.positions, grid.triangles);
  auto b = BuildLaplacianModel(std::span<const float>(flat), grid.triangles);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_TRUE((*a)->differential_coordinates.isApprox((*b)->differential_coordinates, 1e-6));
}

TEST(LaplacianOperator, RejectsBadMeshes) {
  const auto grid = MakeGrid(3, 3, 2, 2);
  auto st = BuildLaplacianModel(Eigen::MatrixX3d(0, 3), grid.triangles).status();
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message(), "the mesh has no vertices");
  st = BuildLaplacianModel(grid.positions, {}).status();
  EXPECT_EQ(st.message(), "the mesh has no triangles");

  Eigen::MatrixX3d nan = grid.positions;
  nan(5, 1) = std::nan("");
  st = BuildLaplacianModel(nan, grid.triangles).status();
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("vertex 5 has a non-finite position"), std::string::npos) << st.message();

  LaplacianModelOptions small;
  small.max_vertices = 8;
  st = BuildLaplacianModel(grid.positions, grid.triangles, small).status();
  EXPECT_EQ(st.code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(st.message(), "the mesh has 9 vertices; the limit is 8");

  const std::vector<float> ragged = {0, 0, 0, 1};
  EXPECT_EQ(BuildLaplacianModel(std::span<const float>(ragged), grid.triangles).status().code(),
            StatusCode::kInvalidArgument);
}

TEST(LaplacianOperator, CotangentRejectsDegenerateTriangles) {
  // Triangle 1 has three collinear vertices (zero area).
  Eigen::MatrixX3d p(5, 3);
  p << 0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 3, 0, 0;
  const std::vector<uint32_t> tri = {0, 1, 2, 1, 3, 4};
  LaplacianModelOptions cot;
  cot.weights = LaplacianWeights::kCotangent;
  const Status st = BuildLaplacianModel(p, tri, cot).status();
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("triangles[1] (vertices 1, 3, 4) is degenerate"), std::string::npos) << st.message();
  // Uniform weights only need the connectivity.
  EXPECT_TRUE(BuildLaplacianModel(p, tri).ok());
}

}  // namespace
}  // namespace armature
