// The mesh slice's handlers, called directly over an in-memory catalog.
#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "armature/engine/anim/clip.h"
#include "armature/engine/mesh/mesh.h"
#include "server/mesh/mesh_handlers.h"

namespace armature::server {
namespace {

using test_util::DemoCatalog;

// SkinMesh by clip and time, and SkinMesh by the local pose that clip gives
// at that time, are two paths through the handler: they must agree.
TEST(MeshHandlers, SkinningByClipEqualsSkinningByItsSampledPose) {
  auto catalog = DemoCatalog();
  const double t = 0.7;
  v1::SkinMeshRequest by_clip;
  by_clip.set_mesh("demo_character.body");
  by_clip.set_clip("demo_character.walk");
  by_clip.set_time(t);
  v1::SkinMeshResponse a;
  Status st = SkinMesh(*catalog, Limits{}, by_clip, &a);
  ASSERT_TRUE(st.ok()) << st.message();

  const auto clip_keys = test_util::StoredKeys(*catalog->FindClip("demo_character.walk")->part);
  const Clip& clip = *clip_keys;
  std::vector<Trs> local(clip.skeleton->size());
  ASSERT_TRUE(SampleClip(clip, t, SampleOptions{}, local).ok());
  v1::SkinMeshRequest by_pose;
  by_pose.set_mesh("demo_character.body");
  for (const Trs& x : local) {
    by_pose.mutable_pose()->add_rotations(static_cast<float>(x.rotation.w()));
    for (int k = 0; k < 3; ++k) by_pose.mutable_pose()->add_rotations(static_cast<float>(x.rotation.vec()[k]));
    for (int k = 0; k < 3; ++k) by_pose.mutable_pose()->add_translations(static_cast<float>(x.translation[k]));
  }
  v1::SkinMeshResponse b;
  st = SkinMesh(*catalog, Limits{}, by_pose, &b);
  ASSERT_TRUE(st.ok()) << st.message();

  ASSERT_GT(a.vertex_count(), 100);
  ASSERT_EQ(a.positions_size(), b.positions_size());
  double worst = 0;
  for (int i = 0; i < a.positions_size(); ++i)
    worst = std::max(worst, std::abs(double(a.positions(i)) - b.positions(i)));
  EXPECT_LT(worst, 1e-3);  // centimetres; the pose went through floats
  // and the pose is not the rest pose: the walk moved the body.
  v1::SkinMeshRequest at_start = by_clip;
  at_start.set_time(0);
  v1::SkinMeshResponse c;
  ASSERT_TRUE(SkinMesh(*catalog, Limits{}, at_start, &c).ok());
  double moved = 0;
  for (int i = 0; i < a.positions_size(); ++i)
    moved = std::max(moved, std::abs(double(a.positions(i)) - c.positions(i)));
  EXPECT_GT(moved, 1.0);
}

TEST(MeshHandlers, MorphWeightsForAMeshWithoutTargetsAreRefusedNamingTheField) {
  auto catalog = DemoCatalog();
  v1::EvaluateBlendshapesRequest request;
  request.set_mesh("demo_character.body");
  request.add_weights(0.5f);
  v1::EvaluateBlendshapesResponse response;
  const Status st = EvaluateBlendshapes(*catalog, request, &response);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("weights"), std::string::npos) << st.message();
}

TEST(MeshHandlers, GeometryIsTheStoredMesh) {
  auto catalog = DemoCatalog();
  v1::GetMeshGeometryRequest request;
  request.set_mesh("demo_character.body");
  v1::MeshGeometry geometry;
  ASSERT_TRUE(GetMeshGeometry(*catalog, request, &geometry).ok());
  const Mesh& mesh = *catalog->FindMesh("demo_character.body")->part->mesh;
  ASSERT_EQ(geometry.vertex_count(), static_cast<int>(mesh.vertex_count()));
  ASSERT_EQ(geometry.triangles_size(), static_cast<int>(mesh.triangles.size()));
  EXPECT_EQ(geometry.positions(3 * 5 + 1), mesh.positions[5].y());
  EXPECT_EQ(geometry.triangles(7), mesh.triangles[7]);
}

}  // namespace
}  // namespace armature::server
