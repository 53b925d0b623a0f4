// The float-lane blend (FloatBlendPlan) against the double blend
// (BlendPath::kDouble) of the same plan on real clips: RobotExpressive's
// Walking, Running and Wave and CMU 01_01 (../shared/data; skipped when
// absent), and clips whose rotations differ by every angle (the slerp's
// whole cosine range). Both sample the same lossy runtime form; they differ
// by the float lanes (|q| − 1 near 1e-7 before the blend) and the slerp's
// series (about 1.4e-7 in its weights).
//
// Bounds, measured and stated: local rotations within 1e-6 rad of the
// double blend's, local translations and world joint positions within 1e-6
// of the skeleton's height.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/anim/motion.h"
#include "armature/engine/io/gltf/gltf.h"
#include "armature/engine/kinematics/fk.h"
#include "../testing/shared_clips.h"

namespace armature {
namespace {

// rad: float rounding (about 3e-7 here) plus the jump at three.js's 0.9995
// cosine, where slerpFlat switches from its sine weights to a normalized
// lerp. A dot within float rounding of it can take one side in float and
// the other in double; the two differ there by up to 1.0145e-6 rad (nlerp
// against slerp at half-angle acos 0.9995, worst at t ≈ 0.21). CMU 01_01
// has such a pose (1.0115e-6 at t 14.78 s, joint Spine).
constexpr double kRotationBound = 1.5e-6;
constexpr double kPositionBound = 1e-6;  // of the skeleton's height

double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return 2 * std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized()))));
}

// The rest pose's extent: the largest distance between two joints' world positions.
double Height(const Skeleton& skeleton) {
  std::vector<Eigen::Affine3d> world(skeleton.size());
  ComputeWorld(skeleton, skeleton.rest, world);
  double h = 0;
  for (const auto& a : world)
    for (const auto& b : world) h = std::max(h, (a.translation() - b.translation()).norm());
  return h;
}

struct Differences {
  double rotation = 0, translation = 0, world = 0;  // rad; skeleton heights
  size_t float_joints = 0, poses = 0;
};

// Both paths at `times`: the largest differences. `reweight` may rescale the
// bound layers' weights (as Playback does) before blending.
template <class Reweight>
Differences Compare(const Motion& motion, const std::vector<double>& times, Reweight reweight) {
  auto lanes = BindMotion(motion, BlendPath::kFloatLanes), doubles = BindMotion(motion, BlendPath::kDouble);
  EXPECT_TRUE(lanes.ok() && doubles.ok());
  if (!lanes.ok() || !doubles.ok()) return {};
  reweight(*lanes);
  reweight(*doubles);
  EXPECT_TRUE(doubles->float_blend.rotations.empty() && doubles->float_blend.translations.empty());
  const Skeleton& skeleton = *lanes->skeleton;
  const double height = Height(skeleton);
  MotionWorkspace lanes_ws, doubles_ws;
  lanes_ws.Resize(*lanes);
  doubles_ws.Resize(*doubles);
  std::vector<Trs> a(skeleton.size()), b(skeleton.size());
  std::vector<Eigen::Affine3d> wa(a.size()), wb(b.size());
  Differences d;
  for (uint8_t f : lanes->float_blend.float_joint) d.float_joints += f;
  for (double t : times) {
    EXPECT_TRUE((BlendMotionJob{&*lanes, t, &lanes_ws, a}.Run().ok()));
    EXPECT_TRUE((BlendMotionJob{&*doubles, t, &doubles_ws, b}.Run().ok()));
    ComputeWorld(skeleton, a, wa);
    ComputeWorld(skeleton, b, wb);
    for (size_t j = 0; j < a.size(); ++j) {
      d.rotation = std::max(d.rotation, AngleBetween(a[j].rotation, b[j].rotation));
      EXPECT_NEAR(a[j].rotation.norm(), 1, 1e-12) << "joint " << j << " at " << t;
      d.translation = std::max(d.translation, (a[j].translation - b[j].translation).norm() / height);
      d.world = std::max(d.world, (wa[j].translation() - wb[j].translation()).norm() / height);
    }
    ++d.poses;
  }
  return d;
}

Differences Compare(const Motion& motion, const std::vector<double>& times) {
  return Compare(motion, times, [](MotionPlan&) {});
}

void ExpectWithinBounds(const Differences& d) {
  EXPECT_GT(d.float_joints, 0u) << "no joint blended in float lanes: nothing was compared";
  EXPECT_GT(d.poses, 0u);
  EXPECT_LE(d.rotation, kRotationBound);
  EXPECT_LE(d.translation, kPositionBound);
  EXPECT_LE(d.world, kPositionBound);
  std::cout << "float blend vs double over " << d.poses << " poses, " << d.float_joints << " float joints: rotation "
            << d.rotation << " rad, translation " << d.translation << ", world " << d.world
            << " (of the skeleton's height)\n";
}

std::vector<double> Times(double until, double step) {
  std::vector<double> t;
  for (double x = 0.013; x < until; x += step) t.push_back(x);
  return t;
}

MotionLayer Layer(std::shared_ptr<const CompressedClip> clip, double weight, double offset = 0) {
  MotionLayer l;
  l.clip = std::move(clip);
  l.clip_name = "c";
  l.weight = weight;
  l.time_offset = offset;
  return l;
}

struct Robot {
  std::shared_ptr<const CompressedClip> walking, running, wave;
};

// RobotExpressive's Walking, Running and Wave at the default bound (empty when the data is absent).
Robot LoadRobot() {
  Robot r;
  for (const test_util::SharedClip& c : test_util::LoadSharedClips()) {
    if (!c.name.starts_with("gltf/RobotExpressive/")) continue;
    auto compressed = CompressClip(c.clip);
    EXPECT_TRUE(compressed.ok());
    if (!compressed.ok()) continue;
    EXPECT_FALSE((*compressed)->exact()) << c.name;
    if (c.name.ends_with("Walking")) r.walking = *compressed;
    if (c.name.ends_with("Running")) r.running = *compressed;
    if (c.name.ends_with("Wave")) r.wave = *compressed;
  }
  return r;
}

#define SKIP_WITHOUT(what) \
  if (!(what)) GTEST_SKIP() << "../shared/data is absent"

TEST(MotionFloatBlend, RobotExpressiveThreeLayersMatchTheDoubleBlend) {
  const Robot r = LoadRobot();
  SKIP_WITHOUT(r.walking && r.running && r.wave);
  Motion m;  // the benchmark's motion (bench/engine/motion_bench.cc)
  m.sync = TimeSync::kPhase;
  m.layers = {Layer(r.walking, 0.6), Layer(r.running, 0.4), Layer(r.wave, 1.0)};
  m.layers[2].mask = {{"ShoulderR", 1.0}};
  ExpectWithinBounds(Compare(m, Times(2 * r.walking->duration, 1.0 / 60)));
  // Weights below 1 in total (the rest pose fills them) and an unmasked third layer.
  m.layers = {Layer(r.walking, 0.35), Layer(r.running, 0.25), Layer(r.wave, 0.3)};
  ExpectWithinBounds(Compare(m, Times(2 * r.walking->duration, 0.0371)));
}

TEST(MotionFloatBlend, RobotExpressiveRootMotionAndAdditiveKeepTheirJointsInDouble) {
  const Robot r = LoadRobot();
  SKIP_WITHOUT(r.walking && r.running && r.wave);
  Motion m;
  m.layers = {Layer(r.walking, 0.7), Layer(r.running, 0.5, 0.2), Layer(r.wave, 0.8)};
  m.layers[2].mode = LayerMode::kAdditive;
  m.layers[2].reference_time = 0.5;
  m.layers[2].mask = {{"ShoulderR", 1.0}};
  m.root_motion = RootMotion::kAccumulate;
  auto plan = BindMotion(m);
  ASSERT_TRUE(plan.ok());
  ASSERT_GE(plan->root, 0);
  EXPECT_FALSE(plan->float_blend.float_joint[plan->root]);
  EXPECT_FALSE(plan->float_blend.float_joint[plan->skeleton->Find("UpperArmR")]);  // the additive layer acts there
  EXPECT_TRUE(plan->float_blend.float_joint[plan->skeleton->Find("UpperLegL")]);
  EXPECT_TRUE(plan->layers[0].float_lanes && plan->layers[0].doubles);  // the root reads it in double
  EXPECT_FALSE(plan->layers[2].float_lanes);
  ExpectWithinBounds(Compare(m, Times(3 * r.walking->duration, 0.0413)));
}

TEST(MotionFloatBlend, RobotExpressiveWeightsRescaledToZeroMatchTheDoubleBlend) {
  const Robot r = LoadRobot();
  SKIP_WITHOUT(r.walking && r.running);
  Motion m;
  m.layers = {Layer(r.walking, 1.0), Layer(r.running, 1.0, 0.3)};
  // As Playback rescales a bound plan: the first layer faded out entirely,
  // the second to 0.4 (the rest pose fills the rest).
  ExpectWithinBounds(Compare(m, Times(r.walking->duration, 0.0291), [](MotionPlan& p) {
    for (double& w : p.layers[0].joint_weight) w = 0;
    for (double& w : p.layers[1].joint_weight) w *= 0.4;
  }));
}

// The layers' lanes hold their clip's still pose from Resize on (the blend
// then writes only animated tracks): a workspace moved to other clips must
// blend as a fresh one does, bit for bit.
TEST(MotionFloatBlend, AWorkspaceReusedForOtherClipsBlendsAsAFreshOne) {
  const Robot r = LoadRobot();
  SKIP_WITHOUT(r.walking && r.running && r.wave);
  Motion first, second;
  first.layers = {Layer(r.walking, 0.6), Layer(r.running, 0.4)};
  second.layers = {Layer(r.running, 0.5), Layer(r.wave, 0.7, 0.2)};
  auto a = BindMotion(first), b = BindMotion(second);
  ASSERT_TRUE(a.ok() && b.ok());
  ASSERT_TRUE(b->layers[0].float_lanes && b->layers[1].float_lanes);
  MotionWorkspace reused, fresh;
  std::vector<Trs> x(a->skeleton->size()), y(x.size());
  reused.Resize(*a);
  ASSERT_TRUE((BlendMotionJob{&*a, 0.37, &reused, x}.Run().ok()));
  reused.Resize(*b);
  fresh.Resize(*b);
  for (double t : {0.05, 0.61, 1.3}) {
    ASSERT_TRUE((BlendMotionJob{&*b, t, &reused, x}.Run().ok()));
    ASSERT_TRUE((BlendMotionJob{&*b, t, &fresh, y}.Run().ok()));
    for (size_t j = 0; j < x.size(); ++j) {
      EXPECT_EQ(x[j].rotation.coeffs(), y[j].rotation.coeffs()) << "joint " << j << " at " << t;
      EXPECT_EQ(x[j].translation, y[j].translation) << "joint " << j << " at " << t;
      EXPECT_EQ(x[j].scale, y[j].scale) << "joint " << j << " at " << t;
    }
  }
}

TEST(MotionFloatBlend, CmuLayersMatchTheDoubleBlend) {
  std::shared_ptr<const CompressedClip> cmu;
  for (const test_util::SharedClip& c : test_util::LoadSharedClips())
    if (c.name == "bvh/cmu_01_01.bvh") cmu = *CompressClip(c.clip);
  SKIP_WITHOUT(cmu);
  ASSERT_FALSE(cmu->exact());
  Motion m;  // one clip at three offsets: poses seconds apart, blended
  m.layers = {Layer(cmu, 0.5), Layer(cmu, 0.3, 2.1), Layer(cmu, 0.9, 7.3)};
  m.layers[2].mask = {{"LeftShoulder", 1.0}, {"RightUpLeg", 0.5}};
  ExpectWithinBounds(Compare(m, Times(cmu->duration, 0.0917)));
}

// Two layers turning the same joints opposite ways about different axes, a
// whole turn each: their rotations meet at every angle (cosines in [0, 1]).
TEST(MotionFloatBlend, RotationsAtEveryAngleMatchTheDoubleBlend) {
  auto skeleton = std::make_shared<Skeleton>();
  const int n = 6;
  for (int j = 0; j < n; ++j) {
    skeleton->names.push_back("j" + std::to_string(j));
    skeleton->parents.push_back(j - 1);
    Trs rest;
    rest.translation = Eigen::Vector3d(0, 0.1, 0);
    skeleton->rest.push_back(rest);
  }
  skeleton->channels.resize(n);
  skeleton->end_sites.resize(n);
  auto turning = [&](const Eigen::Vector3d& axis, double sign) {
    auto clip = std::make_shared<Clip>();
    clip->skeleton = skeleton;
    clip->joints.resize(n);
    clip->duration = 4;
    for (int j = 0; j < n; ++j)
      for (int k = 0; k <= 32; ++k) {
        const double t = clip->duration * k / 32, angle = sign * (1 + 0.3 * j) * 2 * std::numbers::pi * k / 32;
        clip->joints[j].rotation.times.push_back(t);
        clip->joints[j].rotation.values.push_back(Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized())));
      }
    auto compressed = CompressClip(clip);
    EXPECT_TRUE(compressed.ok());
    EXPECT_FALSE((*compressed)->exact());
    return *compressed;
  };
  const auto a = turning(Eigen::Vector3d(0, 0, 1), 1), b = turning(Eigen::Vector3d(1, 0.5, 0), -1);
  // The two clips' rotations do meet at small cosines (the series' 16-term tier).
  double least = 1;
  std::vector<Trs> pa(n), pb(n);
  for (double t : Times(4, 0.01)) {
    ASSERT_TRUE((ClipSamplingJob{a.get(), t, WrapMode::kClamp, nullptr, pa, {}}.Run().ok()));
    ASSERT_TRUE((ClipSamplingJob{b.get(), t, WrapMode::kClamp, nullptr, pb, {}}.Run().ok()));
    for (int j = 0; j < n; ++j) least = std::min(least, std::abs(pa[j].rotation.dot(pb[j].rotation)));
  }
  EXPECT_LT(least, 0.05);
  Motion m;
  m.layers = {Layer(a, 0.55), Layer(b, 0.3)};
  for (MotionLayer& l : m.layers) l.wrap = WrapMode::kClamp;
  ExpectWithinBounds(Compare(m, Times(4, 0.01)));
  m.layers[1].weight = 0.45;  // a total of 1: no rest fill
  ExpectWithinBounds(Compare(m, Times(4, 0.01)));
}

}  // namespace
}  // namespace armature
