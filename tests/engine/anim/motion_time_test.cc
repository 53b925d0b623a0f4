// Motion time (NONE and PHASE sync, wrap) and root motion (IN_PLACE,
// ACCUMULATE, EXTRACT), on hand-made clips and the demo walk.
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/motion.h"
#include "armature/engine/io/demo_walk.h"
#include "../testing/exact_clip.h"

namespace armature {
namespace {

std::shared_ptr<Skeleton> OneRoot() {
  auto s = std::make_shared<Skeleton>();
  s->names = {"root"};
  s->parents = {-1};
  s->rest.resize(1);
  s->channels.resize(1);
  s->end_sites.resize(1);
  return s;
}

// The root's x is the clip time (so a sample shows where the layer plays).
std::shared_ptr<Clip> TimeRamp(double duration) {
  auto c = std::make_shared<Clip>();
  c->skeleton = OneRoot();
  c->joints.resize(1);
  c->duration = duration;
  c->joints[0].translation.times = {0, duration};
  c->joints[0].translation.values = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(duration, 0, 0)};
  return c;
}

MotionLayer Layer(std::shared_ptr<const Clip> clip) {
  MotionLayer l;
  l.clip = test_util::ExactClip(std::move(clip));
  l.clip_name = "c";
  return l;
}

std::vector<Trs> Blend(const MotionPlan& plan, double time, RootDelta* delta = nullptr) {
  MotionWorkspace ws;
  ws.Resize(plan);
  std::vector<Trs> out(plan.skeleton->size());
  const Status st = BlendMotionJob{&plan, time, &ws, out, delta}.Run();
  EXPECT_TRUE(st.ok()) << st.message();
  return out;
}

MotionPlan Bind(const Motion& m) {
  auto plan = BindMotion(m);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  return std::move(*plan);
}

// NONE: time·speed + offset, wrapped per layer: 1.3·2 + 0.5 = 3.1 → 0.1 after 3 loops.
TEST(MotionTime, NoneSyncPlaysEachLayerAtItsOwnTime) {
  Motion m;
  m.layers = {Layer(TimeRamp(1.0)), Layer(TimeRamp(1.0))};
  m.layers[1].speed = 2;
  m.layers[1].time_offset = 0.5;
  const MotionPlan plan = Bind(m);
  EXPECT_NEAR(LayerTimeAt(plan, 0, 1.3).time, 0.3, 1e-12);
  EXPECT_EQ(LayerTimeAt(plan, 0, 1.3).loops, 1);
  EXPECT_NEAR(LayerTimeAt(plan, 1, 1.3).time, 0.1, 1e-12);
  EXPECT_EQ(LayerTimeAt(plan, 1, 1.3).loops, 3);
  m.layers[1].wrap = WrapMode::kClamp;
  EXPECT_NEAR(LayerTimeAt(Bind(m), 1, 1.3).time, 1.0, 1e-12);
  EXPECT_NEAR(LayerTimeAt(Bind(m), 1, -2).time, 0.0, 1e-12);
  // Negative times loop backwards.
  EXPECT_NEAR(LayerTimeAt(plan, 0, -0.25).time, 0.75, 1e-12);
  EXPECT_EQ(LayerTimeAt(plan, 0, -0.25).loops, -1);
}

// PHASE: the first override layer (2 s, speed 1.5, offset 0.2) sets the phase
// frac((t·1.5 + 0.2)/2): at t = 0.6 it is 0.55, and a 0.8 s layer plays at 0.44;
// at t = 1.4 it is 0.15 after one loop.
TEST(MotionTime, PhaseSyncKeepsLayersOfDifferentLengthsInStep) {
  Motion m;
  m.sync = TimeSync::kPhase;
  m.layers = {Layer(TimeRamp(0.8)), Layer(TimeRamp(2.0)), Layer(TimeRamp(0.8))};
  m.layers[0].mode = LayerMode::kAdditive;  // not the driver
  m.layers[1].speed = 1.5;
  m.layers[1].time_offset = 0.2;
  m.layers[2].speed = 7;  // ignored under PHASE
  const MotionPlan plan = Bind(m);
  EXPECT_EQ(plan.phase_layer, 1);
  EXPECT_NEAR(LayerTimeAt(plan, 1, 0.6).time, 1.1, 1e-12);
  EXPECT_NEAR(LayerTimeAt(plan, 2, 0.6).time, 0.44, 1e-12);
  EXPECT_NEAR(LayerTimeAt(plan, 0, 0.6).time, 0.44, 1e-12);
  EXPECT_NEAR(LayerTimeAt(plan, 2, 1.4).time, 0.12, 1e-12);
  EXPECT_EQ(LayerTimeAt(plan, 2, 1.4).loops, 1);
  // The blended pose: layer 1 (x = 1.1) and layer 2 (x = 0.44) at 1 and 1: mean 0.77, plus
  // the additive layer's 0.44 − 0 (reference at 0).
  EXPECT_NEAR(Blend(plan, 0.6)[0].translation.x(), 0.77 + 0.44, 1e-12);
}

// The demo walk: the root advances along +Z at kDemoWalkSpeed and bobs in Y.
MotionPlan DemoWalkPlan(RootMotion mode) {
  const BvhData walk = MakeDemoWalk();
  Motion m;
  m.layers = {Layer(walk.clip)};
  m.root_motion = mode;
  return Bind(m);
}

TEST(RootMotion, InPlaceKeepsTheRootsHorizontalPositionConstant) {
  const MotionPlan plan = DemoWalkPlan(RootMotion::kInPlace);
  EXPECT_EQ(plan.root, 0);
  const Eigen::Vector3d first = Blend(plan, 0)[0].translation;
  double min_y = 1e9, max_y = -1e9;
  for (double t = 0; t < 7; t += 0.0371) {
    const Eigen::Vector3d p = Blend(plan, t)[0].translation;
    EXPECT_NEAR(p.x(), first.x(), 1e-9) << t;
    EXPECT_NEAR(p.z(), first.z(), 1e-9) << t;
    min_y = std::min(min_y, p.y());
    max_y = std::max(max_y, p.y());
  }
  EXPECT_GT(max_y - min_y, 0.5);  // the vertical bob stays
}

// Looping with ACCUMULATE: each loop adds the clip's net displacement
// (kDemoWalkSpeed · duration along +Z), so the root never jumps back.
TEST(RootMotion, AccumulateWalksOnAcrossTheLoopPoint) {
  const MotionPlan keep = DemoWalkPlan(RootMotion::kKeep), acc = DemoWalkPlan(RootMotion::kAccumulate);
  const double d = keep.layers[0].clip->duration;
  const double stride = acc.layers[0].loop_shift.z();
  EXPECT_NEAR(stride, kDemoWalkSpeed * d, 1e-6 * stride);
  EXPECT_NEAR(acc.layers[0].loop_shift.x(), 0, 1e-9);
  ASSERT_GT(d, 1);
  // KEEP jumps back by a whole clip's distance at the loop point.
  const double eps = 1e-6;
  EXPECT_GT(Blend(keep, d - eps)[0].translation.z() - Blend(keep, d + eps)[0].translation.z(), 0.9 * stride);
  for (int loop = 1; loop <= 3; ++loop) {
    const double before = Blend(acc, loop * d - eps)[0].translation.z();
    const double after = Blend(acc, loop * d + eps)[0].translation.z();
    EXPECT_NEAR(after - before, 2 * eps * kDemoWalkSpeed, 1e-3) << loop;
    EXPECT_NEAR(Blend(acc, loop * d + 0.3)[0].translation.z() - Blend(keep, 0.3)[0].translation.z(), loop * stride,
                1e-6);
  }
}

// A root that turns 90° about +Y and moves 1 along +Z per loop: after two
// loops it stands at R_y(90°)·(0,0,1) + (0,0,1) = (1,0,1), turned 180°.
TEST(RootMotion, AccumulateComposesTheLoopsYaw) {
  auto c = TimeRamp(1.0);
  c->joints[0].translation.values = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 1)};
  c->joints[0].rotation.times = {0, 1};
  c->joints[0].rotation.values = {Eigen::Quaterniond::Identity(), Eigen::Quaterniond(Eigen::AngleAxisd(
                                                                      std::numbers::pi / 2, Eigen::Vector3d::UnitY()))};
  Motion m;
  m.layers = {Layer(c)};
  m.root_motion = RootMotion::kAccumulate;
  const MotionPlan plan = Bind(m);
  EXPECT_NEAR(plan.layers[0].loop_yaw, std::numbers::pi / 2, 1e-12);
  const Trs two = Blend(plan, 2.0)[0];
  EXPECT_NEAR((two.translation - Eigen::Vector3d(1, 0, 1)).norm(), 0, 1e-12);
  EXPECT_NEAR(
      two.rotation.angularDistance(Eigen::Quaterniond(Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitY()))),
      0, 1e-9);
  // Half way through the second loop: z 0.5 in the loop's turned frame, from (0,0,1).
  const Trs mid = Blend(plan, 1.5)[0];
  EXPECT_NEAR((mid.translation - Eigen::Vector3d(0.5, 0, 1)).norm(), 0, 1e-12);
  // A million loops stay finite and cheap (log n composition); 10⁶ ≡ 0 mod 4 quarter turns.
  const Trs far = Blend(plan, 1e6)[0];
  EXPECT_TRUE(far.translation.allFinite());
  EXPECT_NEAR(far.rotation.angularDistance(Eigen::Quaterniond::Identity()), 0, 1e-6);
  EXPECT_NEAR(far.translation.norm(), 0, 1e-5);  // four loops return to the start
}

// EXTRACT: the pose is IN_PLACE's, and the delta carries what ACCUMULATE adds.
TEST(RootMotion, ExtractGivesTheInPlacePoseAndTheRootDelta) {
  const MotionPlan ext = DemoWalkPlan(RootMotion::kExtract), in_place = DemoWalkPlan(RootMotion::kInPlace),
                   acc = DemoWalkPlan(RootMotion::kAccumulate);
  for (double t : {0.0, 0.4, 2.9, 3.4, 8.0}) {
    RootDelta delta;
    const auto pose = Blend(ext, t, &delta);
    const auto expected = Blend(in_place, t);
    for (size_t j = 0; j < pose.size(); ++j)
      EXPECT_NEAR((pose[j].translation - expected[j].translation).norm(), 0, 1e-12) << t << " " << j;
    const Eigen::Vector3d accumulated = Blend(acc, t)[0].translation;
    EXPECT_NEAR((pose[0].translation + delta.translation - accumulated).norm(), 0, 1e-9) << t;
    EXPECT_NEAR(delta.translation.y(), 0, 1e-9);  // horizontal only
  }
}

// Root motion acts in world directions: a root under a parent turned −90°
// about X (glTF exports from Z-up tools) moves "horizontally" along its local X and Y.
TEST(RootMotion, InPlaceUsesTheParentsFrame) {
  auto sk = std::make_shared<Skeleton>();
  sk->names = {"armature", "hips"};
  sk->parents = {-1, 0};
  sk->rest.resize(2);
  sk->rest[0].rotation = Eigen::Quaterniond(Eigen::AngleAxisd(-std::numbers::pi / 2, Eigen::Vector3d::UnitX()));
  sk->channels.resize(2);
  sk->end_sites.resize(2);
  auto c = std::make_shared<Clip>();
  c->skeleton = sk;
  c->joints.resize(2);
  c->duration = 1;
  // Local (1, 2, 3) → (4, 6, 8): world = R_x(−90°)·local, so local z is world up.
  c->joints[1].translation.times = {0, 1};
  c->joints[1].translation.values = {Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(4, 6, 8)};
  Motion m;
  m.layers = {Layer(c)};
  m.layers[0].wrap = WrapMode::kClamp;
  m.root_motion = RootMotion::kInPlace;
  const MotionPlan plan = Bind(m);
  EXPECT_EQ(plan.root, 1);
  const Eigen::Vector3d p = Blend(plan, 1.0)[1].translation;
  EXPECT_NEAR((p - Eigen::Vector3d(1, 2, 8)).norm(), 0, 1e-12);
}

}  // namespace
}  // namespace armature
