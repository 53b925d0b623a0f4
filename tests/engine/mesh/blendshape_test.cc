#include "armature/engine/mesh/blendshape.h"

#include <random>

#include <gtest/gtest.h>

#include "armature/engine/math/rotation.h"
#include "../testing/mesh_test_util.h"

namespace armature {
namespace {

// A grid mesh with two full target shapes M_b, turned into sparse targets.
struct Shapes {
  Mesh mesh;
  std::vector<std::vector<Eigen::Vector3f>> full;  // M_b positions per target
};

Shapes MakeShapes() {
  Shapes s;
  s.mesh = test_util::MakeCylinder(1.0, 2.0, 6, 8);  // 48 vertices
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-0.3f, 0.3f);
  for (int t = 0; t < 2; ++t) {
    std::vector<Eigen::Vector3f> shape = s.mesh.positions;
    // Target 0 moves the first ring, target 1 every third vertex.
    for (size_t v = 0; v < shape.size(); ++v)
      if ((t == 0 && v < 8) || (t == 1 && v % 3 == 0)) shape[v] += Eigen::Vector3f(u(rng), u(rng), u(rng));
    std::vector<float> flat;
    for (const auto& p : shape) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
    auto target = MorphTargetFromShape(s.mesh, "t" + std::to_string(t), flat);
    EXPECT_TRUE(target.ok()) << target.status().message();
    s.mesh.targets.push_back(*target);
    s.mesh.default_weights.push_back(0);
    s.full.push_back(shape);
  }
  EXPECT_TRUE(FinalizeMesh(s.mesh).ok());
  return s;
}

TEST(Blendshape, DeltaFormulationWithSparseDeltas) {
  const Shapes s = MakeShapes();
  // Only the moved vertices are stored.
  EXPECT_EQ(s.mesh.targets[0].vertices.size(), 8u);
  EXPECT_EQ(s.mesh.targets[1].vertices.size(), 16u);
  const float weights[2] = {0.7f, -0.4f};
  std::vector<float> out(3 * s.mesh.vertex_count());
  SkinningWorkspace ws;
  BlendshapeJob job;
  job.mesh = &s.mesh;
  job.weights = weights;
  job.positions = out;
  job.workspace = &ws;
  ASSERT_TRUE(job.Run().ok());
  for (size_t v = 0; v < s.mesh.vertex_count(); ++v) {
    // M = M0 + Σ w_b (M_b − M0), from the full shapes.
    const Eigen::Vector3f expected = s.mesh.positions[v] + weights[0] * (s.full[0][v] - s.mesh.positions[v]) +
                                     weights[1] * (s.full[1][v] - s.mesh.positions[v]);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[3 * v + c], expected[c], 1e-6) << v;
  }
  // Empty weights use the mesh's defaults (zero here): the rest shape.
  job.weights = {};
  ASSERT_TRUE(job.Run().ok());
  for (size_t v = 0; v < s.mesh.vertex_count(); ++v) EXPECT_EQ(out[3 * v], s.mesh.positions[v].x());
}

TEST(Blendshape, NormalDeltasAreRenormalized) {
  Mesh m;
  m.name = "quad";
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  m.targets.push_back({"tilt", {1}, {Eigen::Vector3f(0, 0, 1)}, {Eigen::Vector3f(1, 0, -1)}});
  m.default_weights = {1};
  ASSERT_TRUE(FinalizeMesh(m).ok());
  std::vector<float> p(9), n(9);
  SkinningWorkspace ws;
  BlendshapeJob job{&m, {}, true, p, n, &ws};
  ASSERT_TRUE(job.Run().ok());
  EXPECT_FLOAT_EQ(p[5], 1);  // vertex 1 moved up
  // n = (0,0,1) + (1,0,−1) = (1,0,0).
  EXPECT_NEAR(n[3], 1, 1e-6);
  EXPECT_NEAR(n[5], 0, 1e-6);
  // Half way: (0.5, 0, 0.5) → unit.
  const float half[1] = {0.5f};
  job.weights = half;
  ASSERT_TRUE(job.Run().ok());
  EXPECT_NEAR(n[3], std::sqrt(0.5f), 1e-6);
  EXPECT_NEAR(n[5], std::sqrt(0.5f), 1e-6);
}

TEST(Blendshape, CombinedWithSkinningMorphsFirst) {
  Shapes s = MakeShapes();
  auto chain = test_util::MakeChain(1, 1.0);
  s.mesh.joints = {0};
  s.mesh.inverse_bind = {Eigen::Affine3d::Identity()};
  s.mesh.influence_offsets = {0};
  for (size_t v = 0; v < s.mesh.vertex_count(); ++v) {
    s.mesh.influence_joints.push_back(0);
    s.mesh.influence_weights.push_back(1);
    s.mesh.influence_offsets.push_back(static_cast<uint32_t>(v + 1));
  }
  ASSERT_TRUE(FinalizeMesh(s.mesh).ok());
  const float weights[2] = {0.3f, 0.9f};
  std::vector<float> morphed(3 * s.mesh.vertex_count()), skinned(morphed.size());
  SkinningWorkspace ws;
  ASSERT_TRUE((BlendshapeJob{&s.mesh, weights, true, morphed, {}, &ws}.Run().ok()));
  std::vector<Trs> pose = chain->rest;
  pose[0].rotation = AxisRotation(Axis::kY, 0.8);
  pose[0].translation = {1, 2, 3};
  SkinningOptions options;
  options.morph_weights = weights;
  ASSERT_TRUE(SkinPose(s.mesh, *chain, pose, options, skinned, {}, ws).ok());
  const Eigen::Affine3d m = pose[0].ToAffine();
  for (size_t v = 0; v < s.mesh.vertex_count(); ++v) {
    const Eigen::Vector3d expected = m * Eigen::Vector3d(morphed[3 * v], morphed[3 * v + 1], morphed[3 * v + 2]);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(skinned[3 * v + c], expected[c], 1e-5);
  }
}

TEST(Blendshape, BadInput) {
  const Shapes s = MakeShapes();
  std::vector<float> out(3 * s.mesh.vertex_count());
  SkinningWorkspace ws;
  const float one[1] = {1};
  Status st = BlendshapeJob{&s.mesh, one, true, out, {}, &ws}.Run();
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("one per target"), std::string::npos) << st.message();
  const float nan[2] = {0, std::nanf("")};
  st = BlendshapeJob{&s.mesh, nan, true, out, {}, &ws}.Run();
  EXPECT_NE(st.message().find("morph_weights[1] is not finite"), std::string::npos) << st.message();
  EXPECT_EQ((BlendshapeJob{&s.mesh, {}, true, out, {}, nullptr}.Run().code()), StatusCode::kInvalidArgument);

  std::vector<float> short_shape(5);
  EXPECT_EQ(MorphTargetFromShape(s.mesh, "x", short_shape).status().code(), StatusCode::kInvalidArgument);
  std::vector<float> nan_shape(3 * s.mesh.vertex_count(), std::nanf(""));
  EXPECT_EQ(MorphTargetFromShape(s.mesh, "x", nan_shape).status().code(), StatusCode::kInvalidArgument);

  Mesh bad = s.mesh;
  bad.targets[0].vertices[1] = bad.targets[0].vertices[0];  // not increasing
  st = FinalizeMesh(bad);
  EXPECT_NE(st.message().find("targets[0].vertices"), std::string::npos) << st.message();
}

}  // namespace
}  // namespace armature
