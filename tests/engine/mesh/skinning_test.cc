#include "armature/engine/mesh/skinning.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/kinematics/fk.h"
#include "armature/engine/math/rotation.h"
#include "../testing/exact_clip.h"
#include "../testing/mesh_test_util.h"

namespace armature {
namespace {

using test_util::MakeChain;
using test_util::MakeCylinder;

// Straightforward double-precision references, written from the formulas.
Eigen::Vector3d LbsReference(const Mesh& m, const std::vector<Eigen::Affine3d>& world, size_t v,
                             Eigen::Vector3d* normal) {
  Eigen::Matrix4d blend = Eigen::Matrix4d::Zero();
  for (uint32_t i = m.influence_offsets[v]; i < m.influence_offsets[v + 1]; ++i) {
    const uint32_t k = m.influence_joints[i];
    blend += m.influence_weights[i] * (world[static_cast<size_t>(m.joints[k])] * m.inverse_bind[k]).matrix();
  }
  if (normal) *normal = (blend.topLeftCorner<3, 3>() * m.normals[v].cast<double>()).normalized();
  return (blend * m.positions[v].cast<double>().homogeneous()).head<3>();
}

Eigen::Vector3d DqsReference(const Mesh& m, const std::vector<Eigen::Affine3d>& world, size_t v,
                             Eigen::Vector3d* normal) {
  Eigen::Vector4d real = Eigen::Vector4d::Zero(), dual = Eigen::Vector4d::Zero();
  Eigen::Quaterniond pivot;
  for (uint32_t i = m.influence_offsets[v]; i < m.influence_offsets[v + 1]; ++i) {
    const uint32_t k = m.influence_joints[i];
    const Eigen::Affine3d a = world[static_cast<size_t>(m.joints[k])] * m.inverse_bind[k];
    const Eigen::Quaterniond q(a.rotation());
    if (i == m.influence_offsets[v]) pivot = q;
    const double sign = q.coeffs().dot(pivot.coeffs()) < 0 ? -1 : 1;
    const Eigen::Vector3d t = a.translation();
    const Eigen::Quaterniond d = Eigen::Quaterniond(0, t.x(), t.y(), t.z()) * q;  // 2× the dual part
    real += sign * m.influence_weights[i] * q.coeffs();
    dual += sign * m.influence_weights[i] * 0.5 * d.coeffs();
  }
  const double norm = real.norm();
  const Eigen::Quaterniond r(Eigen::Vector4d(real / norm)), d(Eigen::Vector4d(dual / norm));
  const Eigen::Vector3d translation = 2 * (d * r.conjugate()).vec();
  if (normal) *normal = r * m.normals[v].cast<double>();
  return r * m.positions[v].cast<double>() + translation;
}

// A skeleton of `n` joints in a random tree, posed randomly, and a mesh
// whose vertices have 1 … 12 influences (every kernel, including the generic
// one), 20 vertices each: interleaved (v % 12, so no two consecutive
// vertices share a kernel and stores scatter) or, with `grouped`, in runs of
// 20 (whole batches of consecutive vertices, then a partial batch).
struct RandomRig {
  std::shared_ptr<Skeleton> skeleton;
  std::vector<Trs> pose;
  std::vector<Eigen::Affine3d> world;
  Mesh mesh;
};

RandomRig MakeRandomRig(bool uniform_scale, unsigned seed, bool grouped = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  RandomRig r;
  r.skeleton = std::make_shared<Skeleton>();
  const int joints = 14;
  for (int i = 0; i < joints; ++i) {
    r.skeleton->names.push_back("j" + std::to_string(i));
    r.skeleton->parents.push_back(i == 0 ? -1 : static_cast<int>(rng() % static_cast<unsigned>(i)));
    Trs rest;
    rest.translation = {u(rng), u(rng), u(rng)};
    r.skeleton->rest.push_back(rest);
  }
  r.skeleton->channels.resize(joints);
  r.skeleton->end_sites.resize(joints);
  for (int i = 0; i < joints; ++i) {
    Trs t = r.skeleton->rest[static_cast<size_t>(i)];
    t.rotation = ExpQuaternion(Eigen::Vector3d(u(rng), u(rng), u(rng)) * 1.5);
    t.translation += Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.2;
    t.scale = uniform_scale ? Eigen::Vector3d::Constant(1 + 0.3 * u(rng)) : Eigen::Vector3d::Ones();
    r.pose.push_back(t);
  }
  r.world.resize(joints);
  ComputeWorld(*r.skeleton, r.pose, r.world);

  Mesh& m = r.mesh;
  m.name = "random";
  std::vector<Eigen::Affine3d> rest_world(joints);
  ComputeWorld(*r.skeleton, r.skeleton->rest, rest_world);
  // Skin joints are a permutation of the skeleton's, to exercise the indirection.
  for (int k = 0; k < joints; ++k) {
    m.joints.push_back(joints - 1 - k);
    m.inverse_bind.push_back(rest_world[static_cast<size_t>(joints - 1 - k)].inverse());
  }
  m.influence_offsets = {0};
  for (int v = 0; v < 240; ++v) {
    m.positions.emplace_back(Eigen::Vector3f::Random());
    m.normals.emplace_back(Eigen::Vector3f::Random().normalized());
    const int count = 1 + (grouped ? v / 20 : v % 12);
    std::vector<int> chosen(joints);
    std::iota(chosen.begin(), chosen.end(), 0);
    std::shuffle(chosen.begin(), chosen.end(), rng);
    for (int i = 0; i < count; ++i) {
      m.influence_joints.push_back(static_cast<uint32_t>(chosen[static_cast<size_t>(i)]));
      m.influence_weights.push_back(static_cast<float>(0.05 + std::abs(u(rng))));
    }
    m.influence_offsets.push_back(static_cast<uint32_t>(m.influence_joints.size()));
  }
  EXPECT_TRUE(FinalizeMesh(m).ok());
  return r;
}

TEST(Skinning, LinearBlendMatchesTheFormulaForAnyInfluenceCount) {
  for (auto [scaled, grouped] : {std::pair{false, false}, {true, false}, {false, true}, {true, true}}) {
    SCOPED_TRACE(std::string(scaled ? "scaled" : "rigid") + (grouped ? ", grouped" : ", interleaved"));
    const RandomRig r = MakeRandomRig(scaled, 7, grouped);
    const size_t n = r.mesh.vertex_count();
    std::vector<float> positions(3 * n), normals(3 * n);
    SkinningWorkspace ws;
    ASSERT_TRUE(SkinPose(r.mesh, *r.skeleton, r.pose, {}, positions, normals, ws).ok());
    std::vector<size_t> counts(13, 0);
    for (size_t v = 0; v < n; ++v) {
      ++counts[r.mesh.influence_offsets[v + 1] - r.mesh.influence_offsets[v]];
      Eigen::Vector3d normal;
      const Eigen::Vector3d p = LbsReference(r.mesh, r.world, v, &normal);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(positions[3 * v + c], p[c], 2e-5) << "vertex " << v;
        EXPECT_NEAR(normals[3 * v + c], normal[c], 2e-5) << "vertex " << v;
      }
    }
    for (size_t k = 1; k <= 12; ++k) EXPECT_EQ(counts[k], 20u) << k << " influences";
  }
}

TEST(Skinning, DualQuaternionMatchesTheFormulaForAnyInfluenceCount) {
  for (bool grouped : {false, true}) {
    SCOPED_TRACE(grouped ? "grouped" : "interleaved");
    const RandomRig r = MakeRandomRig(false, 11, grouped);
    const size_t n = r.mesh.vertex_count();
    std::vector<float> positions(3 * n), normals(3 * n);
    SkinningWorkspace ws;
    SkinningOptions options;
    options.method = SkinningMethod::kDualQuaternion;
    ASSERT_TRUE(SkinPose(r.mesh, *r.skeleton, r.pose, options, positions, normals, ws).ok());
    for (size_t v = 0; v < n; ++v) {
      Eigen::Vector3d normal;
      const Eigen::Vector3d p = DqsReference(r.mesh, r.world, v, &normal);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(positions[3 * v + c], p[c], 2e-5) << "vertex " << v;
        EXPECT_NEAR(normals[3 * v + c], normal[c], 2e-5) << "vertex " << v;
      }
    }
  }
}

TEST(Skinning, SingleInfluenceIsTheRigidJointTransformForBothMethods) {
  const RandomRig r = MakeRandomRig(false, 3);
  std::vector<float> lbs(3 * r.mesh.vertex_count()), dqs(lbs.size());
  SkinningWorkspace ws;
  SkinningOptions options;
  ASSERT_TRUE(SkinPose(r.mesh, *r.skeleton, r.pose, options, lbs, {}, ws).ok());
  options.method = SkinningMethod::kDualQuaternion;
  ASSERT_TRUE(SkinPose(r.mesh, *r.skeleton, r.pose, options, dqs, {}, ws).ok());
  for (size_t v = 0; v < r.mesh.vertex_count(); v += 12) {  // vertices with one influence
    ASSERT_EQ(r.mesh.influence_offsets[v + 1] - r.mesh.influence_offsets[v], 1u);
    const uint32_t k = r.mesh.influence_joints[r.mesh.influence_offsets[v]];
    const Eigen::Vector3d p =
        r.world[static_cast<size_t>(r.mesh.joints[k])] * r.mesh.inverse_bind[k] * r.mesh.positions[v].cast<double>();
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(lbs[3 * v + c], p[c], 1e-5);
      EXPECT_NEAR(dqs[3 * v + c], p[c], 1e-5);
    }
  }
}

// The area of the polygon the ring's skinned vertices make in the XY plane.
double RingArea(const std::vector<float>& positions, size_t first, int segments) {
  double area = 0;
  for (int s = 0; s < segments; ++s) {
    const size_t a = 3 * (first + static_cast<size_t>(s)), b = 3 * (first + static_cast<size_t>((s + 1) % segments));
    area += positions[a] * positions[b + 1] - positions[b] * positions[a + 1];
  }
  return std::abs(area) / 2;
}

// The candy-wrapper test: twist the second bone of a cylinder by 180°. LBS
// averages the two rotations into a collapse; DQS keeps the cross-section.
TEST(Skinning, DualQuaternionsKeepTheVolumeOfATwistedCylinderWhereLinearBlendCollapses) {
  const int rings = 21, segments = 32;
  Mesh mesh = MakeCylinder(0.25, 2.0, rings, segments);
  auto chain = MakeChain(2, 1.0);
  mesh.joints = {0, 1};
  Eigen::Affine3d bind1 = Eigen::Affine3d::Identity();
  bind1.translation() = Eigen::Vector3d(0, 0, 1);
  mesh.inverse_bind = {Eigen::Affine3d::Identity(), bind1.inverse()};
  mesh.influence_offsets = {0};
  for (const Eigen::Vector3f& p : mesh.positions) {
    const float w1 = std::clamp(p.z() - 0.5f, 0.f, 1.f);  // 0.5/0.5 at the middle ring
    mesh.influence_joints.insert(mesh.influence_joints.end(), {0, 1});
    mesh.influence_weights.insert(mesh.influence_weights.end(), {1 - w1, w1});
    mesh.influence_offsets.push_back(static_cast<uint32_t>(mesh.influence_joints.size()));
  }
  ASSERT_TRUE(FinalizeMesh(mesh).ok());
  std::vector<Trs> pose = chain->rest;
  pose[1].rotation = AxisRotation(Axis::kZ, std::numbers::pi);

  const size_t middle = static_cast<size_t>(rings / 2) * segments;
  std::vector<float> rest(3 * mesh.vertex_count()), lbs(rest.size()), dqs(rest.size());
  SkinningWorkspace ws;
  SkinningOptions options;
  ASSERT_TRUE(SkinPose(mesh, *chain, chain->rest, options, rest, {}, ws).ok());
  ASSERT_TRUE(SkinPose(mesh, *chain, pose, options, lbs, {}, ws).ok());
  options.method = SkinningMethod::kDualQuaternion;
  ASSERT_TRUE(SkinPose(mesh, *chain, pose, options, dqs, {}, ws).ok());
  const double rest_area = RingArea(rest, middle, segments);
  EXPECT_NEAR(rest_area, segments / 2.0 * 0.25 * 0.25 * std::sin(2 * std::numbers::pi / segments), 1e-6);
  EXPECT_LT(RingArea(lbs, middle, segments), 0.01 * rest_area);
  EXPECT_NEAR(RingArea(dqs, middle, segments), rest_area, 0.02 * rest_area);
  // The far end turned rigidly with its bone in both.
  const size_t last = 3 * (mesh.vertex_count() - segments);
  EXPECT_NEAR(lbs[last], -0.25, 1e-5);
  EXPECT_NEAR(dqs[last], -0.25, 1e-5);
}

// Non-uniform scale: positions follow the matrix, normals its inverse transpose.
TEST(Skinning, NormalsUseTheInverseTransposeUnderNonUniformScale) {
  const Skeleton s = *MakeChain(1, 1.0);
  Mesh m;
  m.name = "plane";
  m.positions = {{1, 1, 0}, {0, 0, 0}};
  m.normals = {Eigen::Vector3f(1, 1, 0).normalized(), Eigen::Vector3f(1, 1, 0).normalized()};
  m.joints = {0};
  m.inverse_bind = {Eigen::Affine3d::Identity()};
  m.influence_offsets = {0, 1, 2};
  m.influence_joints = {0, 0};
  m.influence_weights = {1, 1};
  ASSERT_TRUE(FinalizeMesh(m).ok());
  std::vector<Trs> pose = s.rest;
  pose[0].scale = {2, 1, 1};
  const Eigen::Vector3d expected = Eigen::Vector3d(0.5, 1, 0).normalized();  // diag(2,1,1)⁻ᵀ·n
  for (SkinningMethod method : {SkinningMethod::kLinear, SkinningMethod::kDualQuaternion}) {
    std::vector<float> positions(6), normals(6);
    SkinningWorkspace ws;
    SkinningOptions options;
    options.method = method;
    ASSERT_TRUE(SkinPose(m, s, pose, options, positions, normals, ws).ok());
    EXPECT_NEAR(positions[0], 2, 1e-6);
    EXPECT_NEAR(positions[1], 1, 1e-6);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(normals[c], expected[c], 1e-6) << static_cast<int>(method);
  }
}

TEST(Skinning, MorphTargetsApplyBeforeSkinning) {
  auto chain = MakeChain(1, 1.0);
  Mesh m;
  m.name = "morphed";
  m.positions = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.normals = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.joints = {0};
  m.inverse_bind = {Eigen::Affine3d::Identity()};
  m.influence_offsets = {0, 1, 2, 3};
  m.influence_joints = {0, 0, 0};
  m.influence_weights = {1, 1, 1};
  m.targets.push_back({"lift", {1}, {Eigen::Vector3f(0, 0, 2)}, {Eigen::Vector3f(0, -1, 1)}});
  m.default_weights = {0.5f};
  ASSERT_TRUE(FinalizeMesh(m).ok());
  std::vector<Trs> pose = chain->rest;
  pose[0].rotation = AxisRotation(Axis::kX, std::numbers::pi / 2);  // y → z, z → −y
  std::vector<float> positions(9), normals(9);
  SkinningWorkspace ws;
  ASSERT_TRUE(SkinPose(m, *chain, pose, {}, positions, normals, ws).ok());
  // Vertex 1: (0, 1, 0) + 0.5·(0, 0, 2) = (0, 1, 1), rotated → (0, −1, 1).
  EXPECT_NEAR(positions[3], 0, 1e-6);
  EXPECT_NEAR(positions[4], -1, 1e-6);
  EXPECT_NEAR(positions[5], 1, 1e-6);
  // Normal (0, 1, 0) + 0.5·(0, −1, 1) = (0, 0.5, 0.5) → rotated (0, −0.5, 0.5), unit.
  EXPECT_NEAR(normals[4], -std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(normals[5], std::sqrt(0.5), 1e-6);
  // Client weights override the defaults; zero weights give the plain rest shape.
  const float zero[1] = {0};
  SkinningOptions options;
  options.morph_weights = zero;
  ASSERT_TRUE(SkinPose(m, *chain, pose, options, positions, normals, ws).ok());
  EXPECT_NEAR(positions[4], 0, 1e-6);
  EXPECT_NEAR(positions[5], 1, 1e-6);
}

// SkinClip samples the weights track named after the mesh, wrapping time by
// the clip's duration like the joints (a shorter track holds its last key).
TEST(Skinning, ClipWeightsFollowTheClipTimeline) {
  auto chain = MakeChain(1, 1.0);
  Mesh m;
  m.name = "blob";
  m.positions = {{0, 0, 0}};
  m.joints = {0};
  m.inverse_bind = {Eigen::Affine3d::Identity()};
  m.influence_offsets = {0, 1};
  m.influence_joints = {0};
  m.influence_weights = {1};
  m.targets.push_back({"up", {0}, {Eigen::Vector3f(0, 1, 0)}, {}});
  m.default_weights = {0};
  ASSERT_TRUE(FinalizeMesh(m).ok());
  Clip clip;
  clip.skeleton = chain;
  clip.joints.resize(1);
  clip.joints[0].translation.times = {0, 2};
  clip.joints[0].translation.values = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 0, 0)};
  clip.weights.push_back({"blob", 1, {0, 1}, {0, 1}, Interpolation::kLinear});
  clip.duration = 2;
  ASSERT_TRUE(clip.Validate().ok());
  SampleOptions loop;
  loop.wrap = WrapMode::kLoop;
  std::vector<float> p(3);
  SkinningWorkspace ws;
  const std::pair<double, Eigen::Vector3f> cases[] = {
      {0.5, {0.5f, 0.5f, 0}}, {1.5, {1.5f, 1, 0}}, {2.5, {0.5f, 0.5f, 0}}, {3.5, {1.5f, 1, 0}}};
  for (const auto& [t, expected] : cases) {
    ASSERT_TRUE(test_util::SkinExactClip(m, clip, t, loop, {}, p, {}, ws).ok());
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(p[c], expected[c], 1e-6) << "t=" << t;
  }
}

// SkinClip by a clip compressed at the default bound against its exact form,
// at the frames the bound holds at: each joint's world position is within the
// bound and its rotation within bound / shell distance (ACL's virtual points),
// so a vertex at most 4.3 from its joints is within bound·(1 + 4.3 / shell).
// The weights track (kept as stored) applies as well.
TEST(Skinning, ACompressedClipSkinsWithinItsBoundOfTheExactForm) {
  const int rings = 40, segments = 16;
  Mesh mesh = MakeCylinder(0.3, 4.0, rings, segments);
  mesh.name = "tube";
  auto chain = MakeChain(4, 1.0);
  test_util::BindAlongZ(mesh, *chain, 1.0, 3);
  mesh.targets.push_back({"bulge", {0, 5, 100}, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {}});
  mesh.default_weights = {0};
  ASSERT_TRUE(FinalizeMesh(mesh).ok());
  auto clip = std::make_shared<Clip>();
  clip->skeleton = chain;
  clip->joints.resize(chain->size());
  for (size_t j = 0; j < chain->size(); ++j) {
    Track<Eigen::Quaterniond>& r = clip->joints[j].rotation;
    for (int k = 0; k < 5; ++k) {
      r.times.push_back(0.25 * k);
      r.values.push_back(AxisRotation(k % 2 ? Axis::kX : Axis::kY, 0.2 * k + 0.1 * static_cast<double>(j)));
    }
  }
  clip->weights.push_back({"tube", 1, {0, 1}, {0, 1}, Interpolation::kLinear});
  clip->duration = 1;
  ASSERT_TRUE(clip->Validate().ok());
  auto lossy = CompressClip(clip);
  ASSERT_TRUE(lossy.ok()) << lossy.status().message();
  ASSERT_FALSE((*lossy)->exact());
  const auto exact = test_util::ExactClip(clip);
  const ErrorBound& bound = (*lossy)->bound;
  const double tolerance = bound.precision * (1 + 4.3 / bound.shell_distance);
  std::vector<float> p1(3 * mesh.vertex_count()), n1(p1.size()), p2(p1.size()), n2(p1.size());
  SkinningWorkspace ws;
  for (size_t f = 0; f < (*lossy)->frames.count; ++f) {
    const double t = (*lossy)->frames.Time(f);
    ASSERT_TRUE(SkinClip(mesh, *exact, {t}, {}, p1, n1, ws).ok());
    ASSERT_TRUE(SkinClip(mesh, **lossy, {t}, {}, p2, n2, ws).ok());
    double worst = 0;
    for (size_t i = 0; i < p1.size(); ++i) worst = std::max(worst, static_cast<double>(std::abs(p1[i] - p2[i])));
    EXPECT_LE(worst, tolerance + 1e-6) << "t=" << t;  // 1e-6: the float vertices' rounding
  }
  // The weights track applies: at t = 0.5 it gives the bulge 0.5, moving vertex 0 by 0.5 before
  // skinning, which blends rotations of that offset (length at most 0.5).
  std::vector<float> rest(p1.size()), rest_n(p1.size());
  SkinningOptions none;
  const float zero[1] = {0};
  none.morph_weights = zero;
  ASSERT_TRUE(SkinClip(mesh, **lossy, {0.5}, none, rest, rest_n, ws).ok());
  ASSERT_TRUE(SkinClip(mesh, **lossy, {0.5}, {}, p2, n2, ws).ok());
  const float moved = Eigen::Vector3f(p2[0] - rest[0], p2[1] - rest[1], p2[2] - rest[2]).norm();
  EXPECT_GT(moved, 0.25f);
  EXPECT_LE(moved, 0.5f + 1e-5f);
}

TEST(Skinning, TwoThreadsGiveTheSameResultAsOne) {
  const int rings = 400, segments = 100;  // 40000 vertices: above the parallel threshold
  Mesh mesh = MakeCylinder(0.3, 4.0, rings, segments);
  auto chain = MakeChain(4, 1.0);
  test_util::BindAlongZ(mesh, *chain, 1.0, 3);
  mesh.targets.push_back({"bulge", {0, 5, 20000, 39999}, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}}, {}});
  mesh.default_weights = {0.7f};
  ASSERT_TRUE(FinalizeMesh(mesh).ok());
  std::vector<Trs> pose = chain->rest;
  for (size_t i = 0; i < pose.size(); ++i) pose[i].rotation = AxisRotation(Axis::kX, 0.3 * static_cast<double>(i));
  for (SkinningMethod method : {SkinningMethod::kLinear, SkinningMethod::kDualQuaternion}) {
    std::vector<float> p1(3 * mesh.vertex_count()), n1(p1.size()), p2(p1.size()), n2(p1.size());
    SkinningWorkspace ws;
    SkinningOptions options;
    options.method = method;
    options.parallel = false;
    ASSERT_TRUE(SkinPose(mesh, *chain, pose, options, p1, n1, ws).ok());
    options.parallel = true;
    ASSERT_TRUE(SkinPose(mesh, *chain, pose, options, p2, n2, ws).ok());
    EXPECT_EQ(p1, p2);
    EXPECT_EQ(n1, n2);
  }
}

TEST(Skinning, AReusedWorkspaceDoesNotReallocate) {
  const RandomRig r = MakeRandomRig(false, 5);
  std::vector<float> positions(3 * r.mesh.vertex_count()), normals(positions.size());
  SkinningWorkspace ws;
  for (SkinningMethod method : {SkinningMethod::kLinear, SkinningMethod::kDualQuaternion}) {
    SkinningOptions options;
    options.method = method;
    ASSERT_TRUE(SkinPose(r.mesh, *r.skeleton, r.pose, options, positions, normals, ws).ok());
    const void* before[] = {ws.world.data(), ws.matrices.data(), ws.dual_quaternions.data()};
    ASSERT_TRUE(SkinPose(r.mesh, *r.skeleton, r.pose, options, positions, normals, ws).ok());
    const void* after[] = {ws.world.data(), ws.matrices.data(), ws.dual_quaternions.data()};
    for (int i = 0; i < 3; ++i) EXPECT_EQ(before[i], after[i]);
  }
}

TEST(Skinning, BadInputIsRejectedWithAClearMessage) {
  RandomRig r = MakeRandomRig(false, 9);
  const size_t n = r.mesh.vertex_count();
  std::vector<float> positions(3 * n), normals(3 * n), short_out(3 * n - 3);
  SkinningWorkspace ws;
  Status st = SkinPose(r.mesh, *r.skeleton, r.pose, {}, short_out, {}, ws);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("positions"), std::string::npos) << st.message();

  std::vector<Trs> short_pose(r.pose.begin(), r.pose.end() - 1);
  EXPECT_EQ(SkinPose(r.mesh, *r.skeleton, short_pose, {}, positions, {}, ws).code(), StatusCode::kInvalidArgument);

  std::vector<Trs> nan_pose = r.pose;
  nan_pose[3].translation.x() = std::nan("");
  st = SkinPose(r.mesh, *r.skeleton, nan_pose, {}, positions, {}, ws);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("not finite"), std::string::npos) << st.message();

  const float weights[2] = {1, 2};
  SkinningOptions options;
  options.morph_weights = weights;  // the mesh has no targets
  st = SkinPose(r.mesh, *r.skeleton, r.pose, options, positions, {}, ws);
  EXPECT_NE(st.message().find("morph_weights"), std::string::npos) << st.message();

  Mesh no_normals = r.mesh;
  no_normals.normals.clear();
  ASSERT_TRUE(FinalizeMesh(no_normals).ok());
  st = SkinPose(no_normals, *r.skeleton, r.pose, {}, positions, normals, ws);
  EXPECT_NE(st.message().find("normals requested"), std::string::npos) << st.message();

  Mesh raw;
  raw.positions = {{0, 0, 0}};
  std::vector<float> one(3);
  EXPECT_EQ(SkinPose(raw, *r.skeleton, r.pose, {}, one, {}, ws).code(), StatusCode::kFailedPrecondition);

  // A job whose pose is shorter than the skin's joint indices.
  SkinningJob job;
  job.mesh = &r.mesh;
  job.joint_world = std::span<const Eigen::Affine3d>(r.world.data(), 3);
  job.positions = positions;
  job.workspace = &ws;
  st = job.Run();
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("skin joint"), std::string::npos) << st.message();
}

TEST(Skinning, FinalizeNormalizesWeightsAndReportsIt) {
  Mesh m;
  m.name = "m";
  m.positions = {{0, 0, 0}, {1, 0, 0}};
  m.joints = {0, 1};
  m.inverse_bind = {Eigen::Affine3d::Identity(), Eigen::Affine3d::Identity()};
  m.influence_offsets = {0, 2, 4};
  m.influence_joints = {0, 1, 1, 0};
  m.influence_weights = {0.2f, 0.2f, 0.5f, 0.5f};
  std::vector<std::string> warnings;
  ASSERT_TRUE(FinalizeMesh(m, &warnings).ok());
  EXPECT_FLOAT_EQ(m.influence_weights[0], 0.5f);
  EXPECT_FLOAT_EQ(m.influence_weights[1], 0.5f);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("1 vertices"), std::string::npos) << warnings[0];
  EXPECT_EQ(m.max_influences(), 2u);

  m.influence_weights = {0, 0, 1, 0};
  Status st = FinalizeMesh(m);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("vertex 0"), std::string::npos) << st.message();
  m.influence_weights = {1, 0, 1, std::nanf("")};
  EXPECT_EQ(FinalizeMesh(m).code(), StatusCode::kInvalidArgument);
  m.influence_weights = {1, 0, 1, 0};
  m.influence_joints = {0, 1, 1, 7};
  st = FinalizeMesh(m);
  EXPECT_NE(st.message().find("out of range"), std::string::npos) << st.message();
}

}  // namespace
}  // namespace armature
