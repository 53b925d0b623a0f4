// Motion blending against values derived by hand from three.js's
// PropertyMixer rules (accumulate by weight share, rest fill, additive).
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/motion.h"
#include "armature/engine/math/rotation.h"
#include "../testing/exact_clip.h"

namespace armature {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Eigen::Quaterniond Rz(double degrees) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(degrees * kDeg, Eigen::Vector3d::UnitZ()));
}
Eigen::Quaterniond Rx(double degrees) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(degrees * kDeg, Eigen::Vector3d::UnitX()));
}

// Signed angle about Z of a rotation about Z.
double AngleZ(const Eigen::Quaterniond& q) {
  const double a = 2.0 * std::atan2(q.z(), q.w()) / kDeg;
  return std::remainder(a, 360.0);
}

// Joints in order: "hips" (root), "spine" (child of hips), "arm" (child of spine), "leg" (child of hips).
std::shared_ptr<Skeleton> Chain(std::vector<std::string> names = {"hips", "spine", "arm", "leg"}) {
  auto s = std::make_shared<Skeleton>();
  s->names = std::move(names);
  s->parents = {-1, 0, 1, 0};
  s->rest.resize(4);
  for (auto& r : s->rest) r.translation = Eigen::Vector3d(0, 1, 0);
  s->channels.resize(4);
  s->end_sites.resize(4);
  return s;
}

// A clip on `skeleton` whose joints in `animated` rotate about Z from
// `from` to `to` degrees and translate x from `x0` to `x1` over one second.
std::shared_ptr<Clip> Ramp(std::shared_ptr<const Skeleton> skeleton, std::vector<int> animated, double from, double to,
                           double x0 = 0, double x1 = 0) {
  auto c = std::make_shared<Clip>();
  c->skeleton = skeleton;
  c->joints.resize(skeleton->size());
  c->duration = 1;
  for (int j : animated) {
    c->joints[j].rotation.times = {0, 1};
    c->joints[j].rotation.values = {Rz(from), Rz(to)};
    c->joints[j].translation.times = {0, 1};
    c->joints[j].translation.values = {Eigen::Vector3d(x0, 1, 0), Eigen::Vector3d(x1, 1, 0)};
  }
  return c;
}

MotionLayer Layer(std::shared_ptr<const Clip> clip, double weight, LayerMode mode = LayerMode::kOverride) {
  MotionLayer l;
  l.clip = test_util::ExactClip(std::move(clip));
  l.clip_name = "c";
  l.weight = weight;
  l.mode = mode;
  l.wrap = WrapMode::kClamp;  // time 1 is the clips' last key, not their first again
  return l;
}

std::vector<Trs> Blend(const Motion& motion, double time, RootDelta* delta = nullptr) {
  auto plan = BindMotion(motion);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  if (!plan.ok()) return {};
  MotionWorkspace ws;
  ws.Resize(*plan);
  std::vector<Trs> out(plan->skeleton->size());
  BlendMotionJob job{&*plan, time, &ws, out, delta};
  const Status st = job.Run();
  EXPECT_TRUE(st.ok()) << st.message();
  return out;
}

TEST(SlerpFlat, MatchesThreeJsBranches) {
  // Wide angle: the sin formula, angle-linear.
  EXPECT_NEAR(AngleZ(SlerpFlat(Rz(0), Rz(90), 0.5)), 45, 1e-12);
  EXPECT_NEAR(AngleZ(SlerpFlat(Rz(10), Rz(70), 0.25)), 25, 1e-12);
  // Shortest arc: −q is the same rotation.
  EXPECT_NEAR(AngleZ(SlerpFlat(Rz(0), Eigen::Quaterniond(-Rz(90).coeffs()), 0.5)), 45, 1e-12);
  // Within cos 0.9995 (2° apart): lerp then normalize, not exactly angle-linear.
  const Eigen::Quaterniond a = Rz(0), b = Rz(2);
  const Eigen::Vector4d nlerp = (0.75 * a.coeffs() + 0.25 * b.coeffs()).normalized();
  EXPECT_NEAR((SlerpFlat(a, b, 0.25).coeffs() - nlerp).norm(), 0, 1e-15);
}

// Between cosines 0.95 and 0.9995 (the blend's usual case) SlerpFlat sums
// Eberly's series instead of calling acos and sin: the same rotations as
// Eigen's own slerp, to rounding.
TEST(SlerpFlat, SeriesRangeMatchesEigenSlerp) {
  EXPECT_NEAR(AngleZ(SlerpFlat(Rz(10), Rz(30), 0.25)), 15, 1e-12);  // 20° apart: cosine 0.985
  std::mt19937 rng(30);
  std::uniform_real_distribution<double> unit(-1, 1), angle(4.0, 36.0), weight(0, 1);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Quaterniond a(
        Eigen::AngleAxisd(unit(rng) * 3, Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized()));
    const Eigen::Vector3d axis = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
    const Eigen::Quaterniond b = a * Eigen::AngleAxisd(angle(rng) * std::numbers::pi / 180, axis);
    const double t = weight(rng);
    const Eigen::Quaterniond flipped(-b.coeffs());
    EXPECT_NEAR(SlerpFlat(a, flipped, t).angularDistance(a.slerp(t, b)), 0, 1e-13) << i;
    EXPECT_NEAR((SlerpFlat(a, b, t).coeffs() - a.slerp(t, b).coeffs()).norm(), 0, 1e-14) << i;
  }
}

TEST(BlendMotion, OneLayerOfWeightOneIsTheClip) {
  auto sk = Chain();
  auto clip = Ramp(sk, {0, 1}, 0, 80, 0, 4);
  Motion m;
  m.layers = {Layer(clip, 1)};
  const auto out = Blend(m, 0.25);
  std::vector<Trs> ref(4);
  ASSERT_TRUE(SampleClip(*clip, 0.25, {}, ref).ok());
  for (int j = 0; j < 4; ++j) {
    EXPECT_NEAR((out[j].translation - ref[j].translation).norm(), 0, 1e-12) << j;
    EXPECT_NEAR(out[j].rotation.angularDistance(ref[j].rotation), 0, 1e-12) << j;
  }
}

// Two overrides with weights 0.5 and 1 (total ≥ 1): the second is slerped in
// by 1/1.5 of the way: 0° → 90° gives 60°; translation x 0 → 3 gives 2.
TEST(BlendMotion, OverridesAccumulateByWeightShare) {
  auto sk = Chain();
  Motion m;
  m.layers = {Layer(Ramp(sk, {0}, 0, 0, 0, 0), 0.5), Layer(Ramp(sk, {0}, 90, 90, 3, 3), 1.0)};
  const auto out = Blend(m, 0.5);
  EXPECT_NEAR(AngleZ(out[0].rotation), 60, 1e-9);
  EXPECT_NEAR(out[0].translation.x(), 2, 1e-12);
}

// Three layers of weights 0.2, 0.3, 0.1 at 0°, 60°, 90°: 0 → 36° (share 0.6)
// → 45° (share 1/6); total 0.6 < 1, so 40% rest (0°): 27°.
TEST(BlendMotion, TotalWeightBelowOneIsFilledWithTheRestPose) {
  auto sk = Chain();
  Motion m;
  m.layers = {Layer(Ramp(sk, {1}, 0, 0, 10, 10), 0.2), Layer(Ramp(sk, {1}, 60, 60, 10, 10), 0.3),
              Layer(Ramp(sk, {1}, 90, 90, 10, 10), 0.1)};
  const auto out = Blend(m, 0.3);
  EXPECT_NEAR(AngleZ(out[1].rotation), 27, 1e-9);
  // Translation: 0.6·10 + 0.4·rest x (0) = 6.
  EXPECT_NEAR(out[1].translation.x(), 6, 1e-12);
  // Joints no layer animates stay at rest.
  EXPECT_NEAR(out[2].rotation.angularDistance(Eigen::Quaterniond::Identity()), 0, 1e-15);
}

// A joint only the second layer animates gets that layer alone, filled with
// rest by 1 − its weight (three.js binds tracks, not joints).
TEST(BlendMotion, OnlyLayersWithATrackTakePart) {
  auto sk = Chain();
  Motion m;
  m.layers = {Layer(Ramp(sk, {0}, 40, 40), 1.0), Layer(Ramp(sk, {0, 3}, 0, 80), 0.5)};
  const auto out = Blend(m, 1.0);
  EXPECT_NEAR(AngleZ(out[0].rotation), 40 + (80 - 40) / 3.0, 1e-9);  // share 0.5/1.5
  EXPECT_NEAR(AngleZ(out[3].rotation), 40, 1e-9);                    // 80° · 0.5, rest for the other half
}

TEST(BlendMotion, WeightZeroLayerIsSkipped) {
  auto sk = Chain();
  Motion m;
  m.layers = {Layer(Ramp(sk, {0}, 30, 30), 0.0), Layer(Ramp(sk, {0}, 70, 70), 1.0)};
  EXPECT_NEAR(AngleZ(Blend(m, 0)[0].rotation), 70, 1e-9);
}

// Base 30°; the additive clip goes 10° (reference, t = 0) → 50° (t = 1); at
// t = 1 with weight 0.5: 30° + 0.5·40° = 50°. Translation: base x 1, additive
// x 0 → 4: 1 + 0.5·4 = 3.
TEST(BlendMotion, AdditiveLayerAddsTheWeightedDeltaFromItsReference) {
  auto sk = Chain();
  Motion m;
  m.layers = {Layer(Ramp(sk, {0}, 30, 30, 1, 1), 1.0), Layer(Ramp(sk, {0}, 10, 50, 0, 4), 0.5, LayerMode::kAdditive)};
  const auto out = Blend(m, 1.0);
  EXPECT_NEAR(AngleZ(out[0].rotation), 50, 1e-9);
  EXPECT_NEAR(out[0].translation.x(), 3, 1e-12);
  // Reference at t = 0.5 (30°, x 2): delta at t = 1 is 20°, x 2.
  m.layers[1].reference_time = 0.5;
  const auto out2 = Blend(m, 1.0);
  EXPECT_NEAR(AngleZ(out2[0].rotation), 40, 1e-9);
  EXPECT_NEAR(out2[0].translation.x(), 2, 1e-12);
}

// The additive delta multiplies on the right: q = q_blend · slerp(1, q_ref⁻¹·q_clip, w).
TEST(BlendMotion, AdditiveRotationComposesOnTheRight) {
  auto sk = Chain();
  auto base = Ramp(sk, {0}, 0, 0);
  base->joints[0].rotation.values = {Rx(90), Rx(90)};
  Motion m;
  m.layers = {Layer(base, 1.0), Layer(Ramp(sk, {0}, 0, 60), 1.0, LayerMode::kAdditive)};
  const auto out = Blend(m, 1.0);
  EXPECT_NEAR(out[0].rotation.angularDistance(Rx(90) * Rz(60)), 0, 1e-9);
  EXPECT_GT(out[0].rotation.angularDistance(Rz(60) * Rx(90)), 0.5);
}

// The mask covers "spine" and its descendant "arm"; "arm" has its own entry at 0.5.
TEST(BlendMotion, MaskLimitsALayerToJointsAndTheirDescendants) {
  auto sk = Chain();
  Motion m;
  m.layers = {Layer(Ramp(sk, {0, 1, 2, 3}, 0, 0), 1.0), Layer(Ramp(sk, {0, 1, 2, 3}, 90, 90), 1.0)};
  m.layers[1].mask = {{"spine", 1.0}, {"arm", 0.5}};
  const auto out = Blend(m, 0);
  EXPECT_NEAR(AngleZ(out[0].rotation), 0, 1e-9);   // hips: outside the mask
  EXPECT_NEAR(AngleZ(out[3].rotation), 0, 1e-9);   // leg: outside
  EXPECT_NEAR(AngleZ(out[1].rotation), 45, 1e-9);  // spine: 1/(1+1) of the way
  EXPECT_NEAR(AngleZ(out[2].rotation), 30, 1e-9);  // arm: 0.5/(1+0.5) of the way
}

// Layers on another skeleton with the same joint names map by name.
TEST(BlendMotion, ClipsOfAnotherSkeletonMapByJointName) {
  auto sk = Chain();
  auto other = std::make_shared<Skeleton>(*Chain({"hips", "leg", "spine", "arm"}));
  other->parents = {-1, 0, 0, 2};
  Motion m;
  m.layers = {Layer(Ramp(sk, {0}, 0, 0), 1.0), Layer(Ramp(other, {2}, 90, 90), 1.0)};  // other's "spine"
  const auto out = Blend(m, 0);
  EXPECT_NEAR(AngleZ(out[1].rotation), 90, 1e-9);  // the motion's "spine"
  EXPECT_NEAR(AngleZ(out[3].rotation), 0, 1e-9);
}

TEST(BindMotion, ErrorsNameTheLayerAndTheProblem) {
  auto sk = Chain();
  auto clip = Ramp(sk, {0}, 0, 90);
  auto expect_error = [](const Motion& m, StatusCode code, std::vector<std::string> parts) {
    auto plan = BindMotion(m);
    ASSERT_FALSE(plan.ok());
    EXPECT_EQ(plan.status().code(), code) << plan.status().message();
    for (const auto& p : parts)
      EXPECT_NE(plan.status().message().find(p), std::string::npos) << plan.status().message();
  };
  expect_error(Motion{}, StatusCode::kInvalidArgument, {"empty"});
  Motion m;
  m.layers = {Layer(clip, 1.0), Layer(clip, 1.5)};
  m.layers[1].clip_name = "Wave";
  expect_error(m, StatusCode::kInvalidArgument, {"layers[1] (clip 'Wave')", "weight", "[0, 1]"});
  m.layers[1].weight = -0.1;
  expect_error(m, StatusCode::kInvalidArgument, {"layers[1]", "weight"});
  m.layers[1].weight = NAN;
  expect_error(m, StatusCode::kInvalidArgument, {"layers[1]", "weight"});
  m.layers[1].weight = 1;
  m.layers[1].mask = {{"tail", 1}};
  expect_error(m, StatusCode::kNotFound, {"layers[1] (clip 'Wave')", "mask joint 'tail'"});
  m.layers[1].mask = {{"arm", 2}};
  expect_error(m, StatusCode::kInvalidArgument, {"layers[1]", "mask weight", "'arm'"});
  m.layers[1].mask = {};
  m.layers[1].clip = test_util::ExactClip(Ramp(Chain({"hips", "spine", "arm", "tail"}), {0}, 0, 1));
  expect_error(m, StatusCode::kInvalidArgument, {"layers[1] (clip 'Wave')", "lacks 1 of the 4 joints", "'leg'"});
  m.layers[1].clip = nullptr;
  expect_error(m, StatusCode::kInvalidArgument, {"layers[1]", "no clip"});
  Motion additive_only;
  additive_only.layers = {Layer(clip, 1.0, LayerMode::kAdditive)};
  additive_only.sync = TimeSync::kPhase;
  expect_error(additive_only, StatusCode::kInvalidArgument, {"PHASE", "OVERRIDE"});
  Motion bad_speed;
  bad_speed.layers = {Layer(clip, 1.0)};
  bad_speed.layers[0].speed = INFINITY;
  expect_error(bad_speed, StatusCode::kInvalidArgument, {"layers[0]", "speed"});
  bad_speed.layers[0].speed = 1;
  bad_speed.layers[0].mode = static_cast<LayerMode>(7);
  expect_error(bad_speed, StatusCode::kInvalidArgument, {"layers[0]", "mode 7"});
}

TEST(BlendMotionJob, ValidateChecksSizes) {
  auto sk = Chain();
  Motion m;
  m.layers = {Layer(Ramp(sk, {0}, 0, 90), 1.0)};
  auto plan = BindMotion(m);
  ASSERT_TRUE(plan.ok());
  MotionWorkspace ws;
  std::vector<Trs> out(4), small(3);
  EXPECT_EQ(BlendMotionJob({&*plan, 0, &ws, out}).Run().code(), StatusCode::kInvalidArgument);  // unsized workspace
  ws.Resize(*plan);
  EXPECT_EQ(BlendMotionJob({&*plan, 0, &ws, small}).Run().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(BlendMotionJob({&*plan, NAN, &ws, out}).Run().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(BlendMotionJob({nullptr, 0, &ws, out}).Run().code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(BlendMotionJob({&*plan, 0, &ws, out}).Run().ok());
}

}  // namespace
}  // namespace armature
