// The demo character's glb read back by the engine's own importer: its
// skeleton and animation are the demo walk's (checked against the
// independent BVH reference FK), and its skin follows the walk.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/io/asset.h"
#include "armature/engine/io/demo_character.h"
#include "armature/engine/io/demo_walk.h"
#include "armature/engine/kinematics/fk.h"
#include "armature/engine/mesh/mesh.h"
#include "armature/engine/mesh/mesh_topology.h"
#include "armature/engine/mesh/skinning.h"
#include "../testing/exact_clip.h"
#include "../testing/bvh_reference.h"

namespace armature {
namespace {

struct Segment {
  Eigen::Vector3d a, b;
};

double DistanceToSegment(const Segment& s, const Eigen::Vector3d& p) {
  const Eigen::Vector3d ab = s.b - s.a;
  const double t = std::clamp((p - s.a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (s.a + t * ab - p).norm();
}

// The skeleton's bones in `local`'s pose: a segment from each joint to each
// child and to its End Site.
std::vector<Segment> Bones(const Skeleton& sk, std::span<const Trs> local) {
  std::vector<Eigen::Affine3d> world(sk.size());
  ComputeWorld(sk, local, world);
  std::vector<Segment> bones;
  for (size_t j = 0; j < sk.size(); ++j) {
    if (sk.parents[j] >= 0) bones.push_back({world[size_t(sk.parents[j])].translation(), world[j].translation()});
    if (sk.end_sites[j]) bones.push_back({world[j].translation(), world[j] * *sk.end_sites[j]});
  }
  return bones;
}

// The demo walk's bones at `time`, by FK of its BVH clip.
std::vector<Segment> PosedBones(const BvhData& walk, double time) {
  std::vector<Trs> local(walk.skeleton->size());
  EXPECT_TRUE(SampleClip(*walk.clip, time, {}, local).ok());
  return Bones(*walk.skeleton, local);
}

double FarthestFromBones(std::span<const float> xyz, const std::vector<Segment>& bones) {
  double farthest = 0;
  for (size_t v = 0; v < xyz.size() / 3; ++v) {
    const Eigen::Vector3d p(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
    double nearest = INFINITY;
    for (const Segment& s : bones) nearest = std::min(nearest, DistanceToSegment(s, p));
    farthest = std::max(farthest, nearest);
  }
  return farthest;
}

class DemoCharacter : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    auto glb = MakeDemoCharacterGlb();
    ASSERT_TRUE(glb.ok()) << glb.status().message();
    glb_ = new std::string(std::move(*glb));
    auto parsed = ParseAsset(AssetFormat::kGlb, *glb_, "demo_character");
    ASSERT_TRUE(parsed.ok()) << parsed.status().message();
    contents_ = new AssetContents(std::move(*parsed));
  }
  static void TearDownTestSuite() {
    delete glb_;
    delete contents_;
    glb_ = nullptr;
    contents_ = nullptr;
  }
  void SetUp() override {
    ASSERT_TRUE(contents_) << "the glb did not import";
    ASSERT_EQ(contents_->meshes.size(), 1u);
    ASSERT_EQ(contents_->clips.size(), 1u);
    ASSERT_EQ(contents_->skeletons.size(), 1u);
  }
  static const Mesh& Body() { return *contents_->meshes[0].mesh; }
  static const Clip& Walk() { return *contents_->clips[0].clip; }
  // Rest mesh height (feet to crown), the scale tolerances refer to.
  static double Height() {
    float lo = INFINITY, hi = -INFINITY;
    for (const Eigen::Vector3f& p : Body().positions) lo = std::min(lo, p.y()), hi = std::max(hi, p.y());
    return hi - lo;
  }

  static std::string* glb_;
  static AssetContents* contents_;
  const BvhData walk_ = MakeDemoWalk();
};
std::string* DemoCharacter::glb_ = nullptr;
AssetContents* DemoCharacter::contents_ = nullptr;

TEST_F(DemoCharacter, IsADeterministicGlbWithNamedParts) {
  ASSERT_GE(glb_->size(), 12u);
  EXPECT_EQ(glb_->substr(0, 4), "glTF");
  EXPECT_EQ(static_cast<unsigned char>((*glb_)[4]), 2u);  // container version 2
  auto format = DetectFormat("", "", *glb_);
  ASSERT_TRUE(format.ok());
  EXPECT_EQ(*format, AssetFormat::kGlb);
  auto again = MakeDemoCharacterGlb();
  ASSERT_TRUE(again.ok());
  EXPECT_TRUE(*again == *glb_) << "two calls gave different bytes";

  EXPECT_TRUE(contents_->warnings.empty()) << contents_->warnings.front();
  EXPECT_EQ(contents_->skeletons[0].name, "demo_character");
  EXPECT_EQ(contents_->meshes[0].name, "demo_character.body");
  EXPECT_EQ(contents_->meshes[0].skeleton_name, "demo_character");
  EXPECT_EQ(contents_->clips[0].name, "demo_character.walk");
  EXPECT_EQ(contents_->clips[0].skeleton_name, "demo_character");
}

TEST_F(DemoCharacter, SkeletonIsTheDemoWalks) {
  const Skeleton& imported = *contents_->skeletons[0].skeleton;
  const Skeleton& bvh = *walk_.skeleton;
  EXPECT_EQ(imported.names, bvh.names);
  EXPECT_EQ(imported.parents, bvh.parents);
  for (size_t j = 0; j < bvh.size(); ++j) {
    EXPECT_LT((imported.rest[j].translation - bvh.rest[j].translation).norm(), 1e-12) << bvh.names[j];
    EXPECT_LT(imported.rest[j].rotation.angularDistance(bvh.rest[j].rotation), 1e-12) << bvh.names[j];
  }
}

TEST_F(DemoCharacter, BodyIsClosedOutwardAndSkinnedWithAtMostFourWeights) {
  const Mesh& body = Body();
  const size_t n = body.vertex_count();
  EXPECT_GE(n, 4000u);
  EXPECT_LE(n, 12000u);
  ASSERT_EQ(body.normals.size(), n);
  for (const Eigen::Vector3f& normal : body.normals) ASSERT_NEAR(normal.norm(), 1.0, 1e-5);

  // Every body part is a closed surface (each edge on exactly two
  // triangles, once each way) enclosing a positive volume: normals outward.
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (size_t t = 0; t < body.triangles.size(); t += 3)
    for (int e = 0; e < 3; ++e) ++edges[{body.triangles[t + e], body.triangles[t + (e + 1) % 3]}];
  for (const auto& [edge, count] : edges) {
    ASSERT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second << " is used twice the same way";
    ASSERT_EQ(edges.count({edge.second, edge.first}), 1u) << "edge " << edge.first << "-" << edge.second << " is open";
  }
  auto topology = BuildMeshTopology(n, body.triangles);
  ASSERT_TRUE(topology.ok());
  std::vector<double> volume(topology->component_count, 0.0);
  for (size_t t = 0; t < body.triangles.size(); t += 3) {
    const Eigen::Vector3d a = body.positions[body.triangles[t]].cast<double>(),
                          b = body.positions[body.triangles[t + 1]].cast<double>(),
                          c = body.positions[body.triangles[t + 2]].cast<double>();
    volume[topology->component[body.triangles[t]]] += a.dot(b.cross(c)) / 6;
  }
  EXPECT_EQ(topology->component_count, 19u);  // torso, neck, head; per side 4 leg and 4 arm parts
  for (size_t c = 0; c < volume.size(); ++c) EXPECT_GT(volume[c], 10.0) << "part " << c << " (cm³)";

  // The skin: all 19 joints, weights positive, ≤ 4 per vertex, summing to 1.
  ASSERT_EQ(body.joints.size(), walk_.skeleton->size());
  for (size_t k = 0; k < body.joints.size(); ++k) EXPECT_EQ(body.joints[k], static_cast<int>(k));
  ASSERT_EQ(body.influence_offsets.size(), n + 1);
  EXPECT_EQ(body.max_influences(), 4u);
  const Skeleton& sk = *walk_.skeleton;
  size_t left_leg_vertices = 0;
  for (size_t v = 0; v < n; ++v) {
    const uint32_t begin = body.influence_offsets[v], end = body.influence_offsets[v + 1];
    ASSERT_GE(end - begin, 1u);
    ASSERT_LE(end - begin, 4u);
    double sum = 0;
    for (uint32_t i = begin; i < end; ++i) {
      ASSERT_GT(body.influence_weights[i], 0.f);
      sum += body.influence_weights[i];
    }
    ASSERT_NEAR(sum, 1.0, 1e-6) << "vertex " << v;
    // Heat stays on its own surface: nothing of the right side moves the left
    // leg below the pelvis.
    if (body.positions[v].x() > 2 && body.positions[v].y() < -20) {
      ++left_leg_vertices;
      for (uint32_t i = begin; i < end; ++i) {
        const std::string& joint = sk.names[static_cast<size_t>(body.joints[body.influence_joints[i]])];
        ASSERT_NE(joint.rfind("Right", 0), 0u) << "vertex " << v << " on the left leg is weighted to " << joint;
      }
    }
  }
  EXPECT_GT(left_leg_vertices, n / 10);
}

TEST_F(DemoCharacter, AnimationIsTheDemoWalkByReferenceFk) {
  const Clip& walk = Walk();
  EXPECT_NEAR(walk.duration, walk_.clip->duration, 1e-6);
  EXPECT_EQ(walk.frame_count, walk_.clip->frame_count);
  const testing::RefBvh reference = testing::ReadRefBvh(WriteBvh(*walk_.clip));
  const double tolerance = 1e-4 * Height();
  const Skeleton& sk = *contents_->skeletons[0].skeleton;
  std::vector<Trs> local(sk.size());
  // Frames, between frames, and both ends.
  for (double t : {0.0, 0.01, 0.5, 0.77, 1.234, 2.0, 2.51, 2.99, 3.0}) {
    ASSERT_TRUE(SampleClip(walk, t, {}, local).ok());
    const double d =
        testing::MaxDistance(testing::EngineWorldPositions(sk, local), testing::RefWorldPositionsAt(reference, t));
    EXPECT_LT(d, tolerance) << "t = " << t;
  }
  // It walks: the root travels kDemoWalkSpeed along +Z.
  ASSERT_TRUE(SampleClip(walk, 2.0, {}, local).ok());
  const double z2 = local[0].translation.z();
  ASSERT_TRUE(SampleClip(walk, 1.0, {}, local).ok());
  EXPECT_NEAR(z2 - local[0].translation.z(), kDemoWalkSpeed, 1e-3);
}

TEST_F(DemoCharacter, SkinFollowsTheWalk) {
  const Mesh& body = Body();
  SkinningWorkspace workspace;
  std::vector<float> positions(3 * body.vertex_count()), normals(positions.size());
  // In the skeleton's rest pose every vertex lies within the documented
  // distance of a bone.
  const Skeleton& sk = *walk_.skeleton;
  ASSERT_TRUE(SkinPose(body, sk, sk.rest, {}, positions, normals, workspace).ok());
  const double rest_farthest = FarthestFromBones(positions, Bones(sk, sk.rest));
  EXPECT_LE(rest_farthest, kDemoCharacterMaxRadius);
  EXPECT_GT(rest_farthest, kDemoCharacterMaxRadius - 1) << "the documented bound is loose";
  std::cout << "[ demo ] " << body.vertex_count() << " vertices, " << body.triangle_count()
            << " triangles; farthest from a bone: " << rest_farthest << " cm at rest";

  // Skinned by the imported clip, the body stays around the bones that FK of
  // the BVH demo clip gives at the same time (joints bend, so a little slack).
  double walking = 0;
  for (SkinningMethod method : {SkinningMethod::kLinear, SkinningMethod::kDualQuaternion}) {
    SkinningOptions options;
    options.method = method;
    for (double t : {0.0, 0.37, 0.5, 1.25, 2.8}) {
      ASSERT_TRUE(test_util::SkinExactClip(body, Walk(), t, {}, options, positions, normals, workspace).ok());
      const double farthest = FarthestFromBones(positions, PosedBones(walk_, t));
      EXPECT_LE(farthest, rest_farthest + 1.0) << "t = " << t << (method == SkinningMethod::kLinear ? " LBS" : " DQS");
      walking = std::max(walking, farthest);
    }
  }
  std::cout << ", " << walking << " cm walking\n";
}

}  // namespace
}  // namespace armature
