// Root motion across the loop point through EvaluateMotion on a real server:
// the demo walk and RobotExpressive's Walking (../shared/data; skipped when
// absent). With ACCUMULATE the root's world position steps across the loop
// point as it steps between any two frames; with IN_PLACE its horizontal
// position stays where it starts (to float precision: poses travel as floats).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"
#include "support/server_suite.h"

namespace armature::testing {
namespace {

struct Point {
  double x, y, z;
};
double Distance(const Point& a, const Point& b) { return std::hypot(a.x - b.x, a.y - b.y, a.z - b.z); }

class MotionLoop : public ServerSuite {
 protected:
  static void SetUpTestSuite() {
    ServerSuite::SetUpTestSuite();
    const std::string robot = SharedData("gltf/RobotExpressive/RobotExpressive.glb");
    if (!robot.empty()) client::Client(OptionsFor(*server_)).ImportFile(robot, "robot");
  }
  // World positions of `joint` under a one-layer motion of `clip` at `times`.
  static std::vector<Point> RootPath(const std::string& clip, const std::string& joint, v1::Motion::RootMotion mode,
                                     const std::vector<double>& times) {
    v1::EvaluateMotionRequest r;
    r.mutable_motion()->add_layers()->set_clip(clip);
    r.mutable_motion()->set_root_motion(mode);
    for (double t : times) r.add_times(t);
    r.set_space(v1::WORLD);
    r.add_joints(joint);
    const auto got = client::Client(OptionsFor(*server_)).EvaluateMotion(r);
    std::vector<Point> path;
    for (const v1::Pose& p : got.poses()) path.push_back({p.translations(0), p.translations(1), p.translations(2)});
    EXPECT_EQ(path.size(), times.size());
    return path;
  }
  // The clip's frame step: its frame time, else its duration over its most keys.
  static double FrameStep(const v1::ClipInfo& info) {
    return info.frame_time() > 0 ? info.frame_time() : info.duration() / std::max(1, info.frames() - 1);
  }
  // Per loop point k·d (k = 1..3): the root's step from half a frame before to
  // half a frame after, against the largest step between frames in the loop before.
  static void ExpectNoJumpAtLoopPoints(const std::string& clip, const std::string& joint, double jump_factor) {
    const v1::ClipInfo info = client::Client(OptionsFor(*server_)).GetClip(clip);
    const double d = info.duration(), h = FrameStep(info);
    ASSERT_GT(d, 4 * h);
    for (int loop = 1; loop <= 3; ++loop) {
      std::vector<double> times;
      for (double t = (loop - 1) * d + h / 2; t < loop * d - h / 4; t += h) times.push_back(t);
      times.push_back(loop * d + h / 2);  // the last pair straddles the loop point
      const auto acc = RootPath(clip, joint, v1::Motion::ACCUMULATE, times);
      const auto keep = RootPath(clip, joint, v1::Motion::KEEP, times);
      ASSERT_EQ(acc.size(), times.size());
      double largest = 0;
      for (size_t i = 0; i + 2 < acc.size(); ++i) largest = std::max(largest, Distance(acc[i], acc[i + 1]));
      const double across = Distance(acc[acc.size() - 2], acc.back());
      ASSERT_GT(largest, 0);
      EXPECT_LE(across, 1.5 * largest) << clip << " loop " << loop << ": across " << across << ", largest " << largest;
      // KEEP, measured the same way, jumps back when the clip moves the root (the demo walk).
      const double keep_across = Distance(keep[keep.size() - 2], keep.back());
      if (jump_factor > 0) EXPECT_GT(keep_across, jump_factor * largest) << clip << " loop " << loop;
    }
  }
  // The root's horizontal (+Y up) distance from where it starts stays within
  // float precision of its distance from the origin.
  static void ExpectInPlace(const std::string& clip, const std::string& joint) {
    std::vector<double> times;
    for (double t = 0; t < 7; t += 0.0371) times.push_back(t);
    const auto path = RootPath(clip, joint, v1::Motion::IN_PLACE, times);
    const auto keep = RootPath(clip, joint, v1::Motion::KEEP, times);
    ASSERT_FALSE(path.empty());
    const Point first = path[0];
    const double scale = std::hypot(first.x, first.y, first.z);
    double largest = 0, kept = 0, vertical = 0;
    for (size_t i = 0; i < path.size(); ++i) {
      largest = std::max(largest, std::hypot(path[i].x - first.x, path[i].z - first.z));
      kept = std::max(kept, std::hypot(keep[i].x - first.x, keep[i].z - first.z));
      vertical = std::max(vertical, std::abs(path[i].y - first.y));
    }
    EXPECT_LE(largest, 1e-6 * scale) << clip;
    EXPECT_GT(kept, 1e-4 * scale) << clip << ": KEEP moves the root horizontally";
    EXPECT_GT(vertical, 1e-3 * scale) << clip << ": the vertical bob stays";
  }
  static bool HasRobot() { return !SharedData("gltf/RobotExpressive/RobotExpressive.glb").empty(); }
};

TEST_F(MotionLoop, DemoWalkAccumulateDoesNotJumpAtTheLoopPoint) { ExpectNoJumpAtLoopPoints("demo_walk", "Hips", 20); }

TEST_F(MotionLoop, DemoWalkInPlaceKeepsTheRootHorizontallyStill) { ExpectInPlace("demo_walk", "Hips"); }

TEST_F(MotionLoop, RobotExpressiveWalkingAccumulateDoesNotJumpAtTheLoopPoint) {
  if (!HasRobot()) GTEST_SKIP() << "shared data gltf/RobotExpressive/RobotExpressive.glb is absent";
  ExpectNoJumpAtLoopPoints("robot.Walking", "Body", 0);  // an in-place walk: KEEP does not jump either
}

TEST_F(MotionLoop, RobotExpressiveWalkingInPlaceKeepsTheRootHorizontallyStill) {
  if (!HasRobot()) GTEST_SKIP() << "shared data gltf/RobotExpressive/RobotExpressive.glb is absent";
  ExpectInPlace("robot.Walking", "Body");
}

}  // namespace
}  // namespace armature::testing
