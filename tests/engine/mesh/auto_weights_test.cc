#include "armature/engine/mesh/auto_weights.h"

#include <gtest/gtest.h>

#include "armature/engine/io/obj/obj.h"
#include "armature/engine/math/rotation.h"
#include "armature/engine/mesh/skinning.h"
#include "../testing/mesh_test_util.h"

namespace armature {
namespace {

using test_util::MakeChain;
using test_util::MakeCylinder;

// The weight of skeleton joint `joint` at vertex v (0 when not an influence).
double WeightOf(const Mesh& m, size_t v, int joint) {
  for (uint32_t i = m.influence_offsets[v]; i < m.influence_offsets[v + 1]; ++i)
    if (m.joints[m.influence_joints[i]] == joint) return m.influence_weights[i];
  return 0;
}

void ExpectNormalizedAndCapped(const Mesh& m, size_t k) {
  for (size_t v = 0; v < m.vertex_count(); ++v) {
    const uint32_t count = m.influence_offsets[v + 1] - m.influence_offsets[v];
    EXPECT_GE(count, 1u);
    EXPECT_LE(count, k);
    double sum = 0;
    for (uint32_t i = m.influence_offsets[v]; i < m.influence_offsets[v + 1]; ++i) sum += m.influence_weights[i];
    EXPECT_NEAR(sum, 1, 1e-5);
  }
}

class AutoWeights : public ::testing::TestWithParam<WeightMethod> {};

// A cylinder along a 3-bone chain: ends belong to their bone, weights change
// smoothly and monotonically along it, and the bound mesh skins sensibly.
TEST_P(AutoWeights, CylinderAlongAChain) {
  const int rings = 31, segments = 16;
  Mesh rest = MakeCylinder(0.2, 3.0, rings, segments);
  ASSERT_TRUE(FinalizeMesh(rest).ok());
  auto chain = MakeChain(3, 1.0);  // joints at z = 0, 1, 2, end site at 3
  BindOptions options;
  options.method = GetParam();
  options.max_influences = 2;
  auto bound = BindMesh(rest, *chain, options);
  ASSERT_TRUE(bound.ok()) << bound.status().message();
  const Mesh& m = bound->mesh;
  ExpectNormalizedAndCapped(m, 2);
  EXPECT_EQ(m.joints.size(), 3u);

  // Ring r is at z = 3r/30. Bone b spans z ∈ [b, b+1].
  auto ring_weight = [&](int r, int joint) { return WeightOf(m, static_cast<size_t>(r * segments), joint); };
  EXPECT_GT(ring_weight(3, 0), 0.9);   // z = 0.3: inside bone 0
  EXPECT_GT(ring_weight(15, 1), 0.9);  // z = 1.5: middle of bone 1
  EXPECT_GT(ring_weight(27, 2), 0.9);  // z = 2.7: inside bone 2
  // Across the joint at z = 1 the weight moves from bone 0 to bone 1.
  double previous = 1;
  for (int r = 5; r <= 15; ++r) {
    const double w0 = ring_weight(r, 0);
    EXPECT_LE(w0, previous + 1e-6) << "ring " << r;
    previous = w0;
  }
  EXPECT_GT(ring_weight(10, 0), 0.2);
  EXPECT_GT(ring_weight(10, 1), 0.2);
  // Every vertex of a ring has the same weights (the problem is symmetric).
  for (int s = 1; s < segments; ++s) EXPECT_NEAR(WeightOf(m, 10 * segments + s, 0), ring_weight(10, 0), 1e-4);

  // Bending the last bone moves the tip, leaves the root end in place.
  std::vector<Trs> pose = chain->rest;
  pose[2].rotation = AxisRotation(Axis::kX, 1.2);
  std::vector<float> out(3 * m.vertex_count());
  SkinningWorkspace ws;
  ASSERT_TRUE(SkinPose(m, *chain, pose, {}, out, {}, ws).ok());
  EXPECT_NEAR(out[2], 0, 1e-5);  // vertex 0 at z = 0
  const size_t tip = 3 * (m.vertex_count() - segments);
  EXPECT_LT(out[tip + 2], 2.9);
}

INSTANTIATE_TEST_SUITE_P(Methods, AutoWeights, ::testing::Values(WeightMethod::kDistance, WeightMethod::kHeat),
                         [](const auto& info) { return info.param == WeightMethod::kHeat ? "Heat" : "Distance"; });

// Two separate legs: leg A (radius 1) around bone A on the Z axis, and a thin
// leg B whose bone sits 1.8 away. The inner side of leg A is nearer bone B, but
// bone B is on the other side of A's surface: distance weights give it to B,
// bone heat (with visibility) keeps it on A.
TEST(AutoWeightsHeat, BonesBehindTheSurfaceDoNotClaimIt) {
  Mesh a = MakeCylinder(1.0, 2.0, 9, 24);
  Mesh b = MakeCylinder(0.3, 2.0, 9, 12);
  Mesh legs;
  legs.name = "legs";
  legs.positions = a.positions;
  legs.normals = a.normals;
  legs.triangles = a.triangles;
  const auto offset = static_cast<uint32_t>(a.positions.size());
  for (size_t i = 0; i < b.positions.size(); ++i) {
    legs.positions.push_back(b.positions[i] + Eigen::Vector3f(1.8f, 0, 0));
    legs.normals.push_back(b.normals[i]);
  }
  for (uint32_t t : b.triangles) legs.triangles.push_back(t + offset);
  ASSERT_TRUE(FinalizeMesh(legs).ok());

  Skeleton s;
  s.names = {"hips", "leg_a", "leg_b"};
  s.parents = {-1, 0, 0};
  s.rest.resize(3);
  s.rest[0].translation = {0.9, 0, 2.5};
  s.rest[1].translation = {-0.9, 0, -0.5};
  s.rest[2].translation = {0.9, 0, -0.5};
  s.channels.resize(3);
  s.end_sites = {std::nullopt, Eigen::Vector3d(0, 0, -2), Eigen::Vector3d(0, 0, -2)};
  ASSERT_TRUE(s.Validate().ok());

  // Vertex on A's ring at z = 1 facing +X: (1, 0, 1). Bone A is 1 away, bone B 0.8.
  const size_t inner = 4 * 24;
  ASSERT_TRUE(legs.positions[inner].isApprox(Eigen::Vector3f(1, 0, 1), 1e-5f));

  BindOptions options;
  options.method = WeightMethod::kDistance;
  auto distance = BindMesh(legs, s, options);
  ASSERT_TRUE(distance.ok()) << distance.status().message();
  EXPECT_GT(WeightOf(distance->mesh, inner, 2), WeightOf(distance->mesh, inner, 1));

  options.method = WeightMethod::kHeat;
  auto heat = BindMesh(legs, s, options);
  ASSERT_TRUE(heat.ok()) << heat.status().message();
  ExpectNormalizedAndCapped(heat->mesh, 4);
  // Bone A dominates (the rest diffuses in from the hips above), bone B is out.
  EXPECT_GT(WeightOf(heat->mesh, inner, 1), 0.8);
  EXPECT_LT(WeightOf(heat->mesh, inner, 2), 0.05);
  // Leg B's vertices belong to bone B.
  EXPECT_GT(WeightOf(heat->mesh, offset + 4 * 12, 2), 0.9);
}

TEST(AutoWeightsHeat, BindsAnObjMeshToASkeleton) {
  // A box (8 vertices, 12 triangles) from OBJ text around a 2-joint chain.
  const char* box = R"(v -0.3 -0.3 0
v 0.3 -0.3 0
v 0.3 0.3 0
v -0.3 0.3 0
v -0.3 -0.3 2
v 0.3 -0.3 2
v 0.3 0.3 2
v -0.3 0.3 2
f 1 3 2
f 1 4 3
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 2 3 7
f 2 7 6
f 3 4 8
f 3 8 7
f 4 1 5
f 4 5 8
)";
  auto mesh = ParseObj(box, "box");
  ASSERT_TRUE(mesh.ok()) << mesh.status().message();
  auto chain = MakeChain(2, 1.0);
  auto bound = BindMesh(*mesh, *chain, {});
  ASSERT_TRUE(bound.ok()) << bound.status().message();
  ExpectNormalizedAndCapped(bound->mesh, 4);
  // Bottom corners mostly follow bone 0, top corners bone 1.
  for (size_t v = 0; v < 4; ++v) EXPECT_GT(WeightOf(bound->mesh, v, 0), 0.5) << v;
  for (size_t v = 4; v < 8; ++v) EXPECT_GT(WeightOf(bound->mesh, v, 1), 0.5) << v;
  // The inverse bind matrices undo the rest pose: skinning at rest is the identity.
  std::vector<float> out(3 * 8);
  SkinningWorkspace ws;
  ASSERT_TRUE(SkinPose(bound->mesh, *chain, chain->rest, {}, out, {}, ws).ok());
  for (size_t v = 0; v < 8; ++v)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[3 * v + c], mesh->positions[v][c], 1e-5);
}

TEST(AutoWeightsHeat, BadInput) {
  auto chain = MakeChain(2, 1.0);
  Mesh points;
  points.name = "points";
  points.positions = {{0, 0, 0}, {0, 0, 1}};
  ASSERT_TRUE(FinalizeMesh(points).ok());
  auto r = BindMesh(points, *chain, {});
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(r.status().message().find("triangles"), std::string::npos) << r.status().message();
  BindOptions distance;
  distance.method = WeightMethod::kDistance;
  EXPECT_TRUE(BindMesh(points, *chain, distance).ok());  // distance needs no surface
  distance.max_influences = 0;
  EXPECT_EQ(BindMesh(points, *chain, distance).status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace armature
