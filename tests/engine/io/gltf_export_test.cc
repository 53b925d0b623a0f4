// glTF export: a clip written by ExportGltf and read back by our own glTF
// importer has the same joints (names, parents, rest) and the same local
// poses at every key time; interpolation kinds, cubic tangents, meshes with
// their skins and morph targets survive; the size bound holds. Floats are
// what glTF stores, so values agree to 1e-6 relative to their magnitude
// (absolute below 1; angles in radians).
#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/demo_walk.h"
#include "armature/engine/io/gltf/gltf.h"
#include "armature/engine/io/gltf/gltf_writer.h"
#include "armature/engine/mesh/mesh.h"
#include "../testing/mesh_test_util.h"

namespace armature {
namespace {

constexpr double kTolerance = 1e-6;

// glTF times are floats too: a key at t is at float(t) in the file, up to
// 2^-24·t away, which moves a fast joint by more than 1e-6 between keys.
constexpr double kBetweenKeysTolerance = 1e-5;

double Scaled(double magnitude, double tolerance = kTolerance) { return tolerance * std::max(1.0, magnitude); }

AssetContents Reimport(const std::string& bytes, bool binary) {
  auto contents = ParseGltf(bytes, binary, "back");
  EXPECT_TRUE(contents.ok()) << contents.status().message();
  return contents.ok() ? *contents : AssetContents{};
}

void ExpectSameTrs(const Trs& got, const Trs& want, const std::string& where, double tolerance = kTolerance) {
  EXPECT_LE((got.translation - want.translation).norm(), Scaled(want.translation.norm(), tolerance)) << where;
  EXPECT_LE(got.rotation.angularDistance(want.rotation), tolerance) << where;
  EXPECT_LE((got.scale - want.scale).norm(), Scaled(want.scale.norm(), tolerance)) << where;
}

// Every key time of every track of `clip`.
std::set<double> KeyTimes(const Clip& clip) {
  std::set<double> times;
  for (const JointTrack& t : clip.joints) {
    times.insert(t.translation.times.begin(), t.translation.times.end());
    times.insert(t.rotation.times.begin(), t.rotation.times.end());
    times.insert(t.scale.times.begin(), t.scale.times.end());
  }
  return times;
}

// The exported clip, read back, has `original`'s joints by name (parents
// and rest) and its local poses at every key time (within 1e-6; the file's
// key is at float(t)) and between keys (within 1e-5). Returns the number of
// poses compared.
size_t ExpectSameClip(const Clip& original, const Clip& back) {
  const Skeleton &a = *original.skeleton, &b = *back.skeleton;
  EXPECT_EQ(b.size(), a.size());
  std::vector<int> map(a.size(), -1);
  for (size_t j = 0; j < a.size(); ++j) {
    map[j] = b.Find(a.names[j]);
    if (map[j] < 0) {
      ADD_FAILURE() << "joint " << a.names[j] << " is missing after the round trip";
      return 0;
    }
    const int pa = a.parents[j], pb = b.parents[static_cast<size_t>(map[j])];
    EXPECT_EQ(pa < 0 ? "" : a.names[static_cast<size_t>(pa)], pb < 0 ? "" : b.names[static_cast<size_t>(pb)]);
    ExpectSameTrs(b.rest[static_cast<size_t>(map[j])], a.rest[j], "rest of " + a.names[j]);
  }
  const std::set<double> key_times = KeyTimes(original);
  std::vector<double> times(key_times.begin(), key_times.end());
  const size_t keys = times.size();
  for (size_t k = 0; k + 1 < keys; k += std::max<size_t>(1, keys / 20))
    times.push_back((times[k] + times[k + 1]) / 2);  // between keys too
  std::vector<Trs> want(a.size()), got(b.size());
  size_t compared = 0;
  for (size_t i = 0; i < times.size(); ++i) {
    const double t = times[i];
    const bool key = i < keys;
    EXPECT_TRUE(SampleClip(original, t, {}, want).ok());
    EXPECT_TRUE(SampleClip(back, key ? static_cast<float>(t) : t, {}, got).ok());
    for (size_t j = 0; j < a.size(); ++j, ++compared)
      ExpectSameTrs(got[static_cast<size_t>(map[j])], want[j], a.names[j] + " at t=" + std::to_string(t),
                    key ? kTolerance : kBetweenKeysTolerance);
    if (::testing::Test::HasFailure()) break;
  }
  return compared;
}

TEST(GltfExport, BvhClipRoundTripsAsLinearAtItsFrames) {
  const BvhData walk = MakeDemoWalk();
  for (bool binary : {true, false}) {
    auto bytes = ExportGltf(*walk.clip, {}, {.binary = binary, .animation_name = "walk"});
    ASSERT_TRUE(bytes.ok()) << bytes.status().message();
    EXPECT_EQ(bytes->substr(0, 4) == "glTF", binary);
    EXPECT_LE(bytes->size(), GltfExportByteEstimate(*walk.clip, {}, binary));
    const AssetContents back = Reimport(*bytes, binary);
    ASSERT_EQ(back.clips.size(), 1u);
    EXPECT_EQ(back.clips[0].name, "back.walk");
    const Clip& clip = *back.clips[0].clip;
    EXPECT_EQ(clip.frame_count, walk.clip->frame_count);
    EXPECT_NEAR(clip.duration, walk.clip->duration, 1e-6);
    for (const JointTrack& t : clip.joints)
      if (!t.rotation.empty()) EXPECT_EQ(t.rotation.interpolation, Interpolation::kLinear);
    EXPECT_GT(ExpectSameClip(*walk.clip, clip), 1000u);
  }
}

// Found by engine_gltf_writer_fuzz: with no keys and no meshes there is no
// binary data, and the .gltf's empty data uri did not read back.
TEST(GltfExport, ClipWithoutKeysRoundTripsWithNoBuffer) {
  Clip still = *MakeDemoWalk().clip;
  for (JointTrack& track : still.joints) track = JointTrack{};
  ASSERT_TRUE(still.Validate().ok()) << still.Validate().message();
  for (bool binary : {true, false}) {
    auto bytes = ExportGltf(still, {}, {.binary = binary});
    ASSERT_TRUE(bytes.ok()) << bytes.status().message();
    EXPECT_EQ(bytes->find("\"buffers\""), std::string::npos) << *bytes;
    const AssetContents back = Reimport(*bytes, binary);
    ASSERT_EQ(back.skeletons.size(), 1u);
    EXPECT_EQ(back.skeletons[0].skeleton->names, still.skeleton->names);
    EXPECT_TRUE(back.clips.empty());  // glTF has no animation without a channel
  }
}

TEST(GltfExport, CmuBvhClipRoundTrips) {
  const auto text = test_util::ReadFileBytes(test_util::SharedData("bvh/cmu_01_01.bvh"));
  if (!text) GTEST_SKIP() << "shared data " << test_util::SharedData("bvh/cmu_01_01.bvh").string() << " is absent";
  auto bvh = ParseBvh(*text);
  ASSERT_TRUE(bvh.ok()) << bvh.status().message();
  auto bytes = ExportGltf(*bvh->clip);
  ASSERT_TRUE(bytes.ok()) << bytes.status().message();
  const AssetContents back = Reimport(*bytes, true);
  ASSERT_EQ(back.clips.size(), 1u);
  EXPECT_EQ(back.clips[0].clip->frame_count, 2752u);
  EXPECT_GT(ExpectSameClip(*bvh->clip, *back.clips[0].clip), 31u * 2752u);
}

void ExpectSameMesh(const Mesh& got, const Mesh& want, const Skeleton& a, const Skeleton& b) {
  ASSERT_EQ(got.vertex_count(), want.vertex_count()) << want.name;
  EXPECT_EQ(got.name, want.name);
  EXPECT_EQ(got.triangles, want.triangles);
  for (size_t v = 0; v < want.vertex_count(); ++v) {
    EXPECT_EQ(got.positions[v], want.positions[v]) << want.name << " vertex " << v;
    if (!want.normals.empty()) EXPECT_EQ(got.normals[v], want.normals[v]) << want.name << " vertex " << v;
  }
  ASSERT_EQ(got.joints.size(), want.joints.size());
  for (size_t k = 0; k < want.joints.size(); ++k) {
    EXPECT_EQ(b.names[static_cast<size_t>(got.joints[k])], a.names[static_cast<size_t>(want.joints[k])]);
    EXPECT_LE((got.inverse_bind[k].matrix() - want.inverse_bind[k].matrix()).cwiseAbs().maxCoeff(),
              Scaled(want.inverse_bind[k].matrix().cwiseAbs().maxCoeff()));
  }
  EXPECT_EQ(got.influence_offsets, want.influence_offsets);
  EXPECT_EQ(got.influence_joints, want.influence_joints);
  ASSERT_EQ(got.influence_weights.size(), want.influence_weights.size());
  for (size_t i = 0; i < want.influence_weights.size(); ++i)
    EXPECT_NEAR(got.influence_weights[i], want.influence_weights[i], kTolerance);
  ASSERT_EQ(got.targets.size(), want.targets.size());
  for (size_t t = 0; t < want.targets.size(); ++t) {
    const MorphTarget &g = got.targets[t], &w = want.targets[t];
    EXPECT_EQ(g.name, w.name);
    // Zero deltas are not stored sparsely: compare the dense deltas.
    std::vector<Eigen::Vector3f> dg(want.vertex_count(), Eigen::Vector3f::Zero()), dw = dg;
    for (size_t i = 0; i < g.vertices.size(); ++i) dg[g.vertices[i]] = g.position_deltas[i];
    for (size_t i = 0; i < w.vertices.size(); ++i) dw[w.vertices[i]] = w.position_deltas[i];
    EXPECT_EQ(dg, dw) << "target " << w.name;
  }
  EXPECT_EQ(got.default_weights, want.default_weights);
}

// A two-joint arm with a skinned, morphing mesh and a clip using every kind
// of track: STEP, LINEAR, CUBIC with glTF tangents, CUBIC without (resampled),
// scale, and morph weights.
struct Arm {
  std::shared_ptr<Skeleton> skeleton = test_util::MakeChain(2, 1.5);
  Mesh mesh;
  Clip clip;

  Arm() {
    skeleton->rest[1].rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()));
    skeleton->rest[1].scale = {1, 1.25, 1};
    mesh.name = "sleeve";
    for (int i = 0; i < 4; ++i) {
      mesh.positions.push_back(Eigen::Vector3f(0.25f * (i % 2), 0.5f * (i / 2), 1.1f * i));
      mesh.normals.push_back(Eigen::Vector3f(i % 2, 1 - i % 2, 0));
    }
    mesh.triangles = {0, 1, 2, 1, 3, 2};
    mesh.joints = {0, 1};
    mesh.inverse_bind = {Eigen::Affine3d::Identity(), Eigen::Affine3d(Eigen::Translation3d(0, 0, -1.5))};
    mesh.skeleton_root = 0;
    mesh.influence_offsets = {0, 1, 3, 5, 6};
    mesh.influence_joints = {0, 0, 1, 0, 1, 1};
    mesh.influence_weights = {1, 0.75f, 0.25f, 0.375f, 0.625f, 1};
    mesh.targets.push_back({"smile", {1, 3}, {{0, 0.5f, 0}, {0.125f, 0, 0}}, {{0, 0, 0.25f}, {0, 0.5f, 0}}});
    mesh.targets.push_back({"frown", {2}, {{0, -0.5f, 0.75f}}, {}});
    mesh.default_weights = {0.25f, 0};
    EXPECT_TRUE(FinalizeMesh(mesh).ok());

    clip.skeleton = skeleton;
    clip.joints.resize(2);
    clip.duration = 2;
    clip.frame_count = 3;
    Vec3Track& step = clip.joints[0].translation;
    step.times = {0, 0.5, 2};
    step.values = {{0, 0, 0}, {1, 2, 3}, {-4, 0.5, 120.25}};
    step.interpolation = Interpolation::kStep;
    QuatTrack& cubic = clip.joints[1].rotation;
    cubic.times = {0, 1, 2};
    for (double angle : {0.0, 0.9, -0.4})
      cubic.values.push_back(Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d(1, 2, 2).normalized())));
    cubic.in_tangents = {{0, 0, 0, 0}, {0.1, 0.2, -0.3, 0.4}, {0, 0.5, 0, 0}};
    cubic.out_tangents = {{0.2, 0, 0.1, 0}, {-0.1, 0.2, 0.3, 0.1}, {0, 0, 0, 0}};
    cubic.interpolation = Interpolation::kCubic;
    Vec3Track& catmull = clip.joints[1].translation;  // CUBIC without tangents: resampled
    catmull.times = {0, 0.75, 2};
    catmull.values = {{0, 0, 1.5}, {0.5, 0, 1.5}, {0, 1, 2}};
    catmull.interpolation = Interpolation::kCubic;
    Vec3Track& scale = clip.joints[0].scale;
    scale.times = {0.25, 1.75};
    scale.values = {{1, 1, 1}, {2, 0.5, 1}};
    QuatTrack& linear = clip.joints[0].rotation;
    linear.times = {0, 2};
    linear.values = {Eigen::Quaterniond::Identity(), Eigen::Quaterniond(0, 0, 1, 0)};  // a half turn: either way
    WeightsTrack weights;
    weights.mesh = "sleeve";
    weights.targets = 2;
    weights.times = {0, 1};
    weights.values = {0, 1, 0.5, 0.25};
    clip.weights.push_back(weights);
    EXPECT_TRUE(clip.Validate().ok()) << clip.Validate().message();
  }
};

TEST(GltfExport, MeshWithSkinAndMorphTargetsAndEveryTrackKindRoundTrips) {
  const Arm arm;
  const Mesh* meshes[] = {&arm.mesh};
  auto bytes = ExportGltf(arm.clip, meshes, {.binary = false, .animation_name = "wave"});
  ASSERT_TRUE(bytes.ok()) << bytes.status().message();
  EXPECT_NE(bytes->find("data:application/octet-stream;base64,"), std::string::npos);
  EXPECT_LE(bytes->size(), GltfExportByteEstimate(arm.clip, meshes, false));
  const AssetContents back = Reimport(*bytes, false);
  ASSERT_EQ(back.clips.size(), 1u);
  ASSERT_EQ(back.meshes.size(), 1u);
  const Clip& clip = *back.clips[0].clip;
  const Skeleton& skeleton = *back.skeletons[0].skeleton;
  ExpectSameMesh(*back.meshes[0].mesh, arm.mesh, *arm.skeleton, skeleton);
  EXPECT_EQ(back.meshes[0].mesh->skeleton_root, skeleton.Find("bone0"));

  const JointTrack &j0 = clip.joints[static_cast<size_t>(skeleton.Find("bone0"))],
                   &j1 = clip.joints[static_cast<size_t>(skeleton.Find("bone1"))];
  EXPECT_EQ(j0.translation.interpolation, Interpolation::kStep);
  EXPECT_EQ(j0.rotation.interpolation, Interpolation::kLinear);
  EXPECT_EQ(j1.rotation.interpolation, Interpolation::kCubic);
  ASSERT_EQ(j1.rotation.in_tangents.size(), 3u);
  EXPECT_NEAR(j1.rotation.in_tangents[1].y(), -0.3, 1e-7);  // (w, x, y, z) = (0.1, 0.2, -0.3, 0.4)
  EXPECT_NEAR(j1.rotation.out_tangents[0].w(), 0.2, 1e-7);
  // Catmull-Rom is not a glTF sampler: LINEAR at the keys and in between
  // every 1/30 s at most (0.75 s in 23 steps, 1.25 s in 38), where it agrees.
  EXPECT_EQ(j1.translation.interpolation, Interpolation::kLinear);
  ASSERT_EQ(j1.translation.times.size(), 1u + 23 + 38);
  for (double t : j1.translation.times) {
    Trs want = arm.skeleton->rest[1], got = skeleton.rest[static_cast<size_t>(skeleton.Find("bone1"))];
    SampleJoint(arm.clip.joints[1], t, std::nullopt, want);
    SampleJoint(j1, t, std::nullopt, got);
    ExpectSameTrs(got, want, "resampled bone1 at t=" + std::to_string(t));
  }
  // Everything else, at every key and between keys.
  Clip original = arm.clip, copy = clip;
  original.joints[1].translation = {};
  copy.joints[static_cast<size_t>(skeleton.Find("bone1"))].translation = {};
  EXPECT_GT(ExpectSameClip(original, copy), 20u);

  // The morph weights: same keys, sampled the same.
  ASSERT_EQ(clip.weights.size(), 1u);
  EXPECT_EQ(clip.weights[0].mesh, "sleeve");
  for (double t : {0.0, 0.3, 1.0}) {
    double want[2], got[2];
    SampleWeights(arm.clip.weights[0], t, {}, want);
    SampleWeights(clip.weights[0], t, {}, got);
    EXPECT_NEAR(got[0], want[0], kTolerance);
    EXPECT_NEAR(got[1], want[1], kTolerance);
  }
}

TEST(GltfExport, RobotExpressiveClipWithMeshesRoundTrips) {
  const auto path = test_util::SharedData("gltf/RobotExpressive/RobotExpressive.glb");
  auto robot = test_util::LoadGltfFile(path, "robot");
  if (!robot.ok()) GTEST_SKIP() << "shared data " << path.string() << " is absent";
  std::vector<const Mesh*> meshes;
  for (const NamedMesh& m : robot->meshes) meshes.push_back(m.mesh.get());
  ASSERT_GE(meshes.size(), 3u);
  size_t compared = 0;
  for (const NamedClip& named : robot->clips) {
    auto bytes = ExportGltf(*named.clip, meshes);
    ASSERT_TRUE(bytes.ok()) << bytes.status().message();
    EXPECT_LE(bytes->size(), GltfExportByteEstimate(*named.clip, meshes, true));
    const AssetContents back = Reimport(*bytes, true);
    ASSERT_EQ(back.clips.size(), 1u);
    compared += ExpectSameClip(*named.clip, *back.clips[0].clip);
    ASSERT_EQ(back.meshes.size(), meshes.size());
    for (size_t m = 0; m < meshes.size(); ++m)
      ExpectSameMesh(*back.meshes[m].mesh, *meshes[m], *named.clip->skeleton, *back.skeletons[0].skeleton);
    ASSERT_FALSE(HasFailure()) << "clip " << named.name;
    // The morph weights of the face, if the clip animates them.
    EXPECT_EQ(back.clips[0].clip->weights.size(), named.clip->weights.size()) << named.name;
  }
  EXPECT_GT(compared, 10000u);
}

TEST(GltfExport, RefusesBeyondTheByteLimitBeforeWriting) {
  const BvhData walk = MakeDemoWalk();
  // The estimate, plus the animation's name escaped at worst.
  const uint64_t estimate =
      GltfExportByteEstimate(*walk.clip, {}, true) + 6 * GltfExportOptions{}.animation_name.size();
  auto refused = ExportGltf(*walk.clip, {}, {.max_bytes = estimate - 1});
  EXPECT_EQ(refused.status().code(), StatusCode::kResourceExhausted);
  EXPECT_NE(refused.status().message().find(std::to_string(estimate)), std::string::npos) << refused.status().message();
  EXPECT_TRUE(ExportGltf(*walk.clip, {}, {.max_bytes = estimate}).ok());
  // A resampled track over a huge span saturates rather than wraps.
  Clip endless = *walk.clip;
  endless.frame_time = 1e-12;
  endless.joints[1].rotation.interpolation = Interpolation::kCubic;
  endless.joints[1].rotation.times.back() = 1e12;
  endless.duration = 1e12;
  EXPECT_EQ(ExportGltf(endless, {}).status().code(), StatusCode::kResourceExhausted);
}

TEST(GltfExport, RefusesMismatchedInput) {
  const Arm arm;
  Mesh stray = arm.mesh;
  stray.joints = {0, 7};
  const Mesh* meshes[] = {&stray};
  auto out = ExportGltf(arm.clip, meshes);
  EXPECT_EQ(out.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(out.status().message().find("joint 7"), std::string::npos) << out.status().message();
  Clip huge = arm.clip;
  huge.joints[0].translation.values[1].x() = 1e300;
  out = ExportGltf(huge, {});
  EXPECT_EQ(out.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(out.status().message().find("bone0"), std::string::npos) << out.status().message();
}

}  // namespace
}  // namespace armature
