// Root motion across the loop point, on the demo walk and on RobotExpressive's
// Walking (../shared/data; skipped when absent): with ACCUMULATE the root's
// world position steps across the loop point as it steps between any two
// frames; with IN_PLACE its horizontal position stays where it starts.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/motion.h"
#include "armature/engine/io/demo_walk.h"
#include "armature/engine/io/gltf/gltf.h"
#include "armature/engine/kinematics/fk.h"
#include "../testing/exact_clip.h"

namespace armature {
namespace {

const char kRobotFile[] = ARMATURE_SHARED_DATA "/gltf/RobotExpressive/RobotExpressive.glb";

// RobotExpressive's Walking, or null when the shared data is absent.
std::shared_ptr<const Clip> RobotWalking() {
  std::ifstream in(kRobotFile, std::ios::binary);
  if (!in) return nullptr;
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto asset = ParseGltf(bytes, true, "robot");
  EXPECT_TRUE(asset.ok()) << asset.status().message();
  if (!asset.ok()) return nullptr;
  for (const NamedClip& c : asset->clips)
    if (c.name.ends_with("Walking")) return c.clip;
  ADD_FAILURE() << "no Walking clip in " << kRobotFile;
  return nullptr;
}

MotionPlan Plan(std::shared_ptr<const Clip> clip, RootMotion mode) {
  Motion m;
  m.layers.resize(1);
  m.layers[0].clip = test_util::ExactClip(std::move(clip));
  m.layers[0].clip_name = "walk";
  m.root_motion = mode;
  auto plan = BindMotion(m);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  return std::move(*plan);
}

// The root-motion joint's world position at motion time `t` (KEEP names no
// root: the root the other modes choose, joint `root`).
Eigen::Vector3d RootWorld(const MotionPlan& plan, double t, int root = -1) {
  MotionWorkspace ws;
  ws.Resize(plan);
  std::vector<Trs> local(plan.skeleton->size());
  std::vector<Eigen::Affine3d> world(local.size());
  const Status st = BlendMotionJob{&plan, t, &ws, local}.Run();
  EXPECT_TRUE(st.ok()) << st.message();
  ComputeWorld(*plan.skeleton, local, world);
  return world[root >= 0 ? root : plan.root].translation();
}

// The root's step across the loop point `at` (from half a frame `h` before
// to half a frame after), and the largest step between frames inside the loop before it.
struct LoopSteps {
  double across = 0, largest_inside = 0;
};
LoopSteps StepsAround(const MotionPlan& plan, double at, double duration, double h, int root = -1) {
  LoopSteps s;
  s.across = (RootWorld(plan, at + h / 2, root) - RootWorld(plan, at - h / 2, root)).norm();
  for (double t = at - duration + h / 2; t + h < at - h / 4; t += h)
    s.largest_inside = std::max(s.largest_inside, (RootWorld(plan, t + h, root) - RootWorld(plan, t, root)).norm());
  return s;
}

// The clip's frame step: BVH's frame time, else its duration over its most keys.
double FrameStep(const Clip& clip) {
  if (clip.frame_time > 0) return clip.frame_time;
  return clip.duration / static_cast<double>(std::max<size_t>(clip.frame_count, 2) - 1);
}

void ExpectNoJumpAtLoopPoints(const std::shared_ptr<const Clip>& clip) {
  const MotionPlan plan = Plan(clip, RootMotion::kAccumulate);
  const double d = clip->duration, h = FrameStep(*clip);
  ASSERT_GT(d, 4 * h);
  for (int loop = 1; loop <= 3; ++loop) {
    const LoopSteps s = StepsAround(plan, loop * d, d, h);
    ASSERT_GT(s.largest_inside, 0);
    EXPECT_LE(s.across, 1.5 * s.largest_inside)
        << "loop " << loop << ": across " << s.across << ", largest step inside " << s.largest_inside;
  }
}

// Horizontal (world up +Y) distance of the root from where it starts, relative to its distance from the origin.
void ExpectInPlace(const std::shared_ptr<const Clip>& clip) {
  const MotionPlan plan = Plan(clip, RootMotion::kInPlace);
  const MotionPlan keep = Plan(clip, RootMotion::kKeep);
  const Eigen::Vector3d first = RootWorld(plan, 0);
  const double scale = first.norm();
  ASSERT_GT(scale, 0);
  double largest = 0, kept = 0;
  for (double t = 0; t < 3 * clip->duration; t += 0.0371) {
    const Eigen::Vector3d p = RootWorld(plan, t), q = RootWorld(keep, t, plan.root);
    largest = std::max(largest, std::hypot(p.x() - first.x(), p.z() - first.z()));
    kept = std::max(kept, std::hypot(q.x() - first.x(), q.z() - first.z()));
  }
  EXPECT_LE(largest, 1e-9 * scale);
  EXPECT_GT(kept, 1e-4 * scale);  // the clip itself does move the root horizontally
}

TEST(MotionLoop, DemoWalkAccumulateDoesNotJumpAtTheLoopPoint) {
  const BvhData walk = MakeDemoWalk();
  ExpectNoJumpAtLoopPoints(walk.clip);
  // The same measure sees KEEP jump back by a whole clip's distance.
  const MotionPlan keep = Plan(walk.clip, RootMotion::kKeep);
  const double d = walk.clip->duration, h = FrameStep(*walk.clip);
  const LoopSteps s = StepsAround(keep, d, d, h, Plan(walk.clip, RootMotion::kAccumulate).root);
  EXPECT_GT(s.across, 20 * s.largest_inside);
  EXPECT_NEAR(s.across, kDemoWalkSpeed * (d - h), 0.01 * kDemoWalkSpeed * d);
}

TEST(MotionLoop, DemoWalkInPlaceKeepsTheRootHorizontallyStill) { ExpectInPlace(MakeDemoWalk().clip); }

TEST(MotionLoop, RobotExpressiveWalkingAccumulateDoesNotJumpAtTheLoopPoint) {
  if (!std::filesystem::exists(kRobotFile)) GTEST_SKIP() << "shared data " << kRobotFile << " is absent";
  const auto walking = RobotWalking();
  ASSERT_TRUE(walking);
  EXPECT_EQ(walking->skeleton->names[Plan(walking, RootMotion::kAccumulate).root], "Body");
  ExpectNoJumpAtLoopPoints(walking);
}

TEST(MotionLoop, RobotExpressiveWalkingInPlaceKeepsTheRootHorizontallyStill) {
  if (!std::filesystem::exists(kRobotFile)) GTEST_SKIP() << "shared data " << kRobotFile << " is absent";
  const auto walking = RobotWalking();
  ASSERT_TRUE(walking);
  ExpectInPlace(walking);
}

}  // namespace
}  // namespace armature
