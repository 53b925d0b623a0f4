#include "armature/engine/io/obj/obj.h"

#include <gtest/gtest.h>

#include "armature/engine/io/asset.h"

namespace armature {
namespace {

std::vector<uint32_t> Triangles(const Mesh& m) { return m.triangles; }

TEST(Obj, ParsesEveryFaceFormatAndKeepsTheFileVertexOrder) {
  const char* text = R"(# a comment
mtllib box.mtl
o thing
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0.5 0.5 1   # trailing comment
vt 0 0
vt 1 0
vt 1 1
vn 0 0 -1
vn 0 0 2
g side
usemtl red
s off
f 1 2 3
f 1/1 3/2 4/3
f 1//1 2//1 5//2
f 2/1/1 3/2/1 5/3/2
f -5 -1 -2
)";
  std::vector<std::string> warnings;
  auto mesh = ParseObj(text, "thing", &warnings);
  ASSERT_TRUE(mesh.ok()) << mesh.status().message();
  ASSERT_EQ(mesh->vertex_count(), 5u);
  EXPECT_EQ(mesh->positions[4], Eigen::Vector3f(0.5f, 0.5f, 1));
  EXPECT_EQ(mesh->name, "thing");
  EXPECT_EQ(Triangles(*mesh), (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 0, 1, 4, 1, 2, 4, 0, 4, 3}));
  EXPECT_FALSE(mesh->skinned());
  // Vertex 4's corners name vn 2 (normalized); vertex 0 only vn 1.
  EXPECT_TRUE(mesh->normals[4].isApprox(Eigen::Vector3f(0, 0, 1)));
  EXPECT_TRUE(mesh->normals[0].isApprox(Eigen::Vector3f(0, 0, -1)));
  // Vertex 3 has no vn in any face: computed from its faces, and reported.
  EXPECT_NEAR(mesh->normals[3].norm(), 1, 1e-6);
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings[0].find("no 'vn'"), std::string::npos) << warnings[0];
  EXPECT_EQ(mesh->layout.order.size(), 5u);  // finalized
}

TEST(Obj, PolygonsAreFanTriangulated) {
  auto mesh = ParseObj("v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4 5\n", "pentagon");
  ASSERT_TRUE(mesh.ok()) << mesh.status().message();
  EXPECT_EQ(mesh->triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 0, 3, 4}));
  // No vn at all: normals come from the faces (counter-clockwise in XY → +Z).
  for (const auto& n : mesh->normals) EXPECT_TRUE(n.isApprox(Eigen::Vector3f(0, 0, 1))) << n.transpose();
}

TEST(Obj, LineContinuationsAndCrlfAreHandled) {
  auto mesh = ParseObj("v 0 0 0\r\nv 1 0 0\r\nv 0 1 \\\r\n 0\r\nf 1 2 \\\n 3\r\n", "m");
  ASSERT_TRUE(mesh.ok()) << mesh.status().message();
  EXPECT_EQ(mesh->vertex_count(), 3u);
  EXPECT_EQ(mesh->positions[2], Eigen::Vector3f(0, 1, 0));
  EXPECT_EQ(mesh->triangle_count(), 1u);
}

struct BadObj {
  const char* text;
  const char* expected;  // substring of the error
};

class ObjErrors : public ::testing::TestWithParam<BadObj> {};

TEST_P(ObjErrors, NameTheLine) {
  auto mesh = ParseObj(GetParam().text, "bad");
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(mesh.status().message().find(GetParam().expected), std::string::npos) << mesh.status().message();
}

INSTANTIATE_TEST_SUITE_P(
    Cases, ObjErrors,
    ::testing::Values(BadObj{"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
                             "line 4: vertex index 4 is out of range (3 vertices so far)"},
                      BadObj{"v 0 0 0\nf 1 2 3\nv 1 0 0\nv 0 1 0\n", "line 2: vertex index 2 is out of range"},
                      BadObj{"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "line 4: vertex index 0 is out of range"},
                      BadObj{"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", "line 4: vertex index -4"},
                      BadObj{"v 0 0 0\nv 1 0 0\n\nf 1 2\n", "line 4: a face needs at least 3 vertices"},
                      BadObj{"v 0 0\n", "line 1: expected 3 numbers after 'v'"},
                      BadObj{"# x\nv 0 zero 0\n", "line 2: 'zero' is not a number"},
                      BadObj{"v 0 nan 0\n", "line 1: 'nan' is not a finite float"},
                      BadObj{"v 0 1e39 0\n", "line 1: '1e39' is not a finite float"},
                      BadObj{"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//2 2//1 3//1\n",
                             "line 4: normal index 2 is out of range (0 normals so far)"},
                      BadObj{"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/x 2 3\n", "line 4: 'x' is not a texture coordinate index"},
                      BadObj{"# only a comment\n", "no vertices"}));

TEST(Obj, ImportsThroughParseAssetAsAnUnboundMesh) {
  auto format = DetectFormat("", "body.obj", "");
  ASSERT_TRUE(format.ok());
  EXPECT_EQ(*format, AssetFormat::kObj);
  auto contents = ParseAsset(AssetFormat::kObj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "body");
  ASSERT_TRUE(contents.ok()) << contents.status().message();
  ASSERT_EQ(contents->meshes.size(), 1u);
  EXPECT_EQ(contents->meshes[0].name, "body");
  EXPECT_EQ(contents->meshes[0].skeleton_name, "");
  EXPECT_EQ(contents->meshes[0].mesh->triangle_count(), 1u);
}

}  // namespace
}  // namespace armature
