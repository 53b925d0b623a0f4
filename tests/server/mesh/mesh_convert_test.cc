// The mesh slice's conversions: skinning method, the clip that poses a mesh
// (its own skeleton's, or another mapped by joint name), the motion that
// poses it, and the reply's size counted before the work.
#include "server/mesh/mesh_convert.h"

#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"

namespace armature::server {
namespace {

const NamedMesh& Body(const Catalog& catalog) { return *catalog.FindMesh("demo_character.body")->part; }

TEST(MeshConvert, SkinningMethodsMapAndAnUnknownOneIsRefused) {
  EXPECT_EQ(*FromProto(v1::SKINNING_METHOD_UNSPECIFIED), SkinningMethod::kLinear);
  EXPECT_EQ(*FromProto(v1::LBS), SkinningMethod::kLinear);
  EXPECT_EQ(*FromProto(v1::DQS), SkinningMethod::kDualQuaternion);
  const Status st = FromProto(static_cast<v1::SkinningMethod>(99)).status();
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message(), "method: unknown skinning method 99");
}

TEST(MeshConvert, AClipOfTheMeshsSkeletonNeedsNoMap) {
  auto catalog = test_util::DemoCatalog();
  auto clip = ClipFor(*catalog, Body(*catalog), "demo_character.walk");
  ASSERT_TRUE(clip.ok()) << clip.status().message();
  EXPECT_EQ(clip->clip_ref.part->name, "demo_character.walk");
  EXPECT_EQ(clip->skeleton_ref.part, nullptr);
  EXPECT_TRUE(clip->joint_map.empty());
  const Status unknown = ClipFor(*catalog, Body(*catalog), "Wave").status();
  EXPECT_EQ(unknown.code(), StatusCode::kNotFound);
  EXPECT_TRUE(unknown.message().starts_with("clip: ")) << unknown.message();
}

TEST(MeshConvert, AClipOfAnotherSkeletonIsMappedByJointName) {
  auto catalog = test_util::DemoCatalog();
  auto clip = ClipFor(*catalog, Body(*catalog), "demo_walk");
  ASSERT_TRUE(clip.ok()) << clip.status().message();
  ASSERT_NE(clip->skeleton_ref.part, nullptr);
  EXPECT_EQ(clip->skeleton_ref.part->name, "demo_character");
  const Skeleton& mesh_skeleton = *clip->skeleton_ref.part->skeleton;
  const Skeleton& clip_skeleton = *clip->clip_ref.part->runtime->skeleton;
  ASSERT_EQ(clip->joint_map.size(), mesh_skeleton.size());
  for (size_t j = 0; j < mesh_skeleton.size(); ++j)
    EXPECT_EQ(clip->joint_map[j], clip_skeleton.Find(mesh_skeleton.names[j])) << mesh_skeleton.names[j];
}

TEST(MeshConvert, AClipLackingJointsOfTheMeshsSkeletonIsRefused) {
  auto base = test_util::DemoCatalog();
  auto stump = std::make_shared<Skeleton>();
  stump->names = {"Hips"};
  stump->parents = {-1};
  stump->rest.resize(1);
  auto clip = std::make_shared<Clip>();
  clip->skeleton = stump;
  clip->joints.resize(1);
  auto asset = std::make_shared<StoredAsset>();
  asset->record.name = "stump";
  asset->contents.skeletons.push_back({"stump", stump});
  asset->contents.clips.push_back({"stump", "stump", clip});
  ASSERT_TRUE(CompressClips(asset->contents, ClipPrecision{.exact = true}).ok());
  auto assets = base->assets;
  assets["stump"] = asset;
  auto catalog = BuildCatalog(std::move(assets));
  ASSERT_TRUE(catalog.ok());
  const Status st = ClipFor(**catalog, Body(**catalog), "stump").status();
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(st.message().starts_with("clip: 'stump' animates skeleton 'stump', which ")) << st.message();
  EXPECT_NE(st.message().find("LeftKnee"), std::string::npos) << st.message();
}

// The demo walk mapped onto the character, and the character's own walk (the
// same clip stored as glTF, demo_character.h), skin the body alike.
TEST(MeshConvert, SkinningByAMappedClipEqualsSkinningByTheMeshsOwnCopyOfIt) {
  auto catalog = test_util::DemoCatalog();
  const Mesh& mesh = *Body(*catalog).mesh;
  auto own = ClipFor(*catalog, Body(*catalog), "demo_character.walk");
  auto mapped = ClipFor(*catalog, Body(*catalog), "demo_walk");
  ASSERT_TRUE(own.ok() && mapped.ok());
  const size_t n = 3 * mesh.vertex_count();
  std::vector<float> pa(n), na(n), pb(n), nb(n), rest(n);
  SkinningWorkspace workspace;
  for (double t : {0.5, 1.25}) {
    ASSERT_TRUE(SkinByClip(mesh, *own, t, SampleOptions{}, SkinningOptions{}, pa, na, workspace).ok());
    ASSERT_TRUE(SkinByClip(mesh, *mapped, t, SampleOptions{}, SkinningOptions{}, pb, nb, workspace).ok());
    double worst = 0, moved = 0;
    for (size_t i = 0; i < n; ++i) {
      worst = std::max(worst, std::abs(double(pa[i]) - pb[i]));
      moved = std::max(moved, std::abs(double(pa[i]) - mesh.positions[i / 3][static_cast<int>(i % 3)]));
    }
    EXPECT_LT(worst, 1e-2) << "at " << t;  // centimetres; glTF stores floats
    EXPECT_GT(moved, 1.0) << "at " << t;   // and the pose is not the bind pose
  }
}

TEST(MeshConvert, AMotionMustStartWithAClipOfTheMeshsSkeleton) {
  auto catalog = test_util::DemoCatalog();
  v1::Motion motion;
  motion.add_layers()->set_clip("demo_walk");
  const Status st = MotionFor(*catalog, Body(*catalog), motion, Limits{}).status();
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message(),
            "motion.layers[0] (clip 'demo_walk'): animates skeleton 'demo_walk', not the mesh's skeleton "
            "'demo_character'");
  motion.mutable_layers(0)->set_clip("demo_character.walk");
  motion.add_layers()->set_clip("demo_walk");  // later layers map by name
  auto plan = MotionFor(*catalog, Body(*catalog), motion, Limits{});
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  EXPECT_EQ(plan->skeleton, catalog->FindSkeleton("demo_character")->part->skeleton);
  EXPECT_EQ(plan->layers.size(), 2u);
  v1::Motion empty;
  EXPECT_EQ(MotionFor(*catalog, Body(*catalog), empty, Limits{}).status().message(),
            "motion.layers: the motion is empty (give at least one layer)");
}

// Protobuf: 4 bytes per float, a varint per triangle index, 64 bytes besides.
double ProtobufBytes(const Mesh& mesh, bool triangles) {
  double bytes = 64 + 4.0 * 3 * mesh.vertex_count() * (mesh.normals.empty() ? 1 : 2);
  if (!triangles) return bytes;
  bytes += 4.0 * 2 * mesh.uvs.size();
  for (uint32_t i : mesh.triangles) bytes += i < (1u << 7) ? 1 : i < (1u << 14) ? 2 : 3;
  return bytes;
}

TEST(MeshConvert, AMeshReplyIsRefusedJustOverTheMessageLimit) {
  auto catalog = test_util::DemoCatalog();
  const Mesh& mesh = *Body(*catalog).mesh;
  ASSERT_LT(mesh.vertex_count(), 1u << 14);  // 2-byte varints at most, as counted above
  for (bool triangles : {false, true}) {
    const auto bytes = static_cast<int64_t>(ProtobufBytes(mesh, triangles));
    Limits limits;
    limits.max_message_bytes = bytes;
    EXPECT_TRUE(ValidateMeshReply(mesh, triangles, limits, "GetMeshGeometry").ok()) << triangles;
    limits.max_message_bytes = bytes - 1;
    const Status st = ValidateMeshReply(mesh, triangles, limits, "GetMeshGeometry");
    EXPECT_EQ(st.code(), StatusCode::kResourceExhausted) << triangles;
    EXPECT_TRUE(st.message().starts_with("GetMeshGeometry: ")) << st.message();
    const std::string counted = std::to_string(mesh.vertex_count()) + " vertices" +
                                (triangles ? " and " + std::to_string(mesh.triangle_count()) + " triangles" : "");
    EXPECT_NE(st.message().find(counted + "; imports are capped by --max-mesh-vertices"), std::string::npos)
        << st.message();
  }
}

TEST(MeshConvert, JsonCountsFiveBytesAFloatAndEachIndexsDigits) {
  auto catalog = test_util::DemoCatalog();
  const Mesh& mesh = *Body(*catalog).mesh;
  ASSERT_LT(mesh.vertex_count(), 10000u);
  double bytes = 64 + 5.0 * (3 * mesh.vertex_count() * 2 + 2 * mesh.uvs.size());
  for (uint32_t i : mesh.triangles) bytes += 1 + std::to_string(i).size();  // digits and a comma
  Limits limits;
  limits.max_message_bytes = static_cast<int64_t>(bytes);
  EXPECT_TRUE(ValidateMeshReply(mesh, true, limits, "GetMeshGeometry", ReplyEncoding::kJson).ok());
  limits.max_message_bytes -= 1;
  EXPECT_EQ(ValidateMeshReply(mesh, true, limits, "GetMeshGeometry", ReplyEncoding::kJson).code(),
            StatusCode::kResourceExhausted);
  // By name: the same check, and an unknown mesh is left to the RPC to report.
  EXPECT_EQ(ValidateMeshReply(*catalog, "demo_character.body", true, limits, "G", ReplyEncoding::kJson).code(),
            StatusCode::kResourceExhausted);
  EXPECT_TRUE(ValidateMeshReply(*catalog, "nobody", true, limits, "G", ReplyEncoding::kJson).ok());
}

TEST(MeshConvert, ACharacterReplySumsItsMeshes) {
  auto catalog = test_util::DemoCatalog();
  const NamedMesh& body = Body(*catalog);
  const std::vector<const NamedMesh*> twice = {&body, &body};
  const auto bytes = static_cast<int64_t>(2 * ProtobufBytes(*body.mesh, false));
  Limits limits;
  limits.max_message_bytes = bytes;
  EXPECT_TRUE(ValidateCharacterReply(twice, limits, "SkinCharacter").ok());
  limits.max_message_bytes = bytes - 1;
  const Status st = ValidateCharacterReply(twice, limits, "SkinCharacter");
  EXPECT_EQ(st.code(), StatusCode::kResourceExhausted);
  EXPECT_NE(st.message().find("2 meshes, " + std::to_string(2 * body.mesh->vertex_count()) + " vertices in all"),
            std::string::npos)
      << st.message();
}

}  // namespace
}  // namespace armature::server
