// Clips on other skeletons by joint name (anim/joint_map.h): the map, the
// message naming missing joints, sampling onto the target's rest, and the
// same rule in BindMotion.
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/joint_map.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/motion.h"
#include "../testing/exact_clip.h"

namespace armature {
namespace {

std::shared_ptr<Skeleton> Named(std::vector<std::string> names, double bone) {
  auto s = std::make_shared<Skeleton>();
  for (size_t j = 0; j < names.size(); ++j) {
    s->names.push_back(names[j]);
    s->parents.push_back(static_cast<int>(j) - 1);  // a chain
    Trs rest;
    rest.translation = Eigen::Vector3d(0, bone, 0);
    s->rest.push_back(rest);
  }
  s->channels.resize(names.size());
  s->end_sites.resize(names.size());
  return s;
}

Eigen::Quaterniond Rz(double degrees) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(degrees * std::numbers::pi / 180, Eigen::Vector3d::UnitZ()));
}

TEST(JointMap, MapsByNameAndIgnoresExtraSourceJoints) {
  const auto target = Named({"a", "b", "c"}, 1);
  const auto source = Named({"x", "c", "a", "b"}, 2);
  std::vector<int> map;
  ASSERT_TRUE(MapJointsByName(*target, *source, "the target", map).ok());
  EXPECT_EQ(map, (std::vector<int>{2, 3, 1}));
  ASSERT_TRUE(MapJointsByName(*target, *target, "itself", map).ok());
  EXPECT_EQ(map, (std::vector<int>{0, 1, 2}));
}

TEST(JointMap, MissingJointsAreNamedFirstFiveThenCounted) {
  const auto target = Named({"a", "b", "c", "d", "e", "f", "g", "h"}, 1);
  std::vector<int> map;
  Status st = MapJointsByName(*target, *Named({"a", "c", "x"}, 1), "the mesh's skeleton 'm'", map);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message(), "lacks 6 of the 8 joints of the mesh's skeleton 'm': 'b', 'd', 'e', 'f', 'g' and 1 more");
  st = MapJointsByName(*Named({"a", "b"}, 1), *Named({"a", "B"}, 1), "t", map);
  EXPECT_EQ(st.message(), "lacks 1 of the 2 joints of t: 'b'");  // names are case-sensitive
}

// Untracked parts keep the target's rest (its bone lengths); tracked parts
// come from the clip's joint of the same name.
TEST(JointMap, TheOntoJobTakesTracksByNameAndTheTargetsRest) {
  const auto target = Named({"root", "mid", "tip"}, 1);
  const auto source = Named({"tip", "root", "mid"}, 5);
  Clip clip;
  clip.skeleton = source;
  clip.joints.resize(3);
  clip.duration = 2;
  clip.joints[0].rotation = {{0, 2}, {Rz(0), Rz(90)}};                                          // source "tip"
  clip.joints[1].translation = {{0, 2}, {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(4, 0, 0)}};  // source "root"
  std::vector<int> map;
  ASSERT_TRUE(MapJointsByName(*target, *source, "t", map).ok());
  std::vector<Trs> out(3);
  const auto exact = test_util::ExactClip(clip);
  ClipSamplingContext context(*exact);
  ASSERT_TRUE(
      (ClipSamplingOntoJob{exact.get(), map, target.get(), 1.0, WrapMode::kClamp, &context, out, {}}.Run().ok()));
  EXPECT_TRUE(out[0].translation.isApprox(Eigen::Vector3d(2, 0, 0)));  // half of the root's track
  EXPECT_TRUE(out[0].rotation.isApprox(Eigen::Quaterniond::Identity()));
  EXPECT_EQ(out[1].translation, Eigen::Vector3d(0, 1, 0));  // the target's bone, not the source's 5
  EXPECT_NEAR(out[2].rotation.angularDistance(Rz(45)), 0, 1e-12);
  EXPECT_EQ(out[2].translation, Eigen::Vector3d(0, 1, 0));
  // Wrong sizes are an error, not a read out of bounds.
  const std::vector<int> short_map{0, 1}, bad_map{0, 1, 7};
  EXPECT_FALSE(
      (ClipSamplingOntoJob{exact.get(), short_map, target.get(), 1.0, WrapMode::kClamp, &context, out, {}}.Run().ok()));
  EXPECT_FALSE(
      (ClipSamplingOntoJob{exact.get(), bad_map, target.get(), 1.0, WrapMode::kClamp, &context, out, {}}.Run().ok()));
}

// Motion layers follow the same rule: a clip with more joints binds, one
// with fewer is refused naming them.
TEST(JointMap, MotionLayersBindByTheSameRule) {
  const auto motion_skeleton = Named({"a", "b"}, 1);
  auto clip_of = [](std::shared_ptr<Skeleton> s) {
    auto c = std::make_shared<Clip>();
    c->skeleton = s;
    c->joints.resize(s->size());
    c->duration = 1;
    return c;
  };
  Motion m;
  MotionLayer first, second;
  first.clip = test_util::ExactClip(clip_of(motion_skeleton));
  second.clip = test_util::ExactClip(clip_of(Named({"b", "extra", "a"}, 1)));
  second.clip_name = "wider";
  m.layers = {first, second};
  auto plan = BindMotion(m);
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  EXPECT_EQ(plan->layers[1].clip_joint, (std::vector<int>{2, 0}));
  m.layers[1].clip = test_util::ExactClip(clip_of(Named({"b"}, 1)));
  m.layers[1].clip_name = "narrow";
  plan = BindMotion(m);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.status().message(),
            "layers[1] (clip 'narrow'): the clip's skeleton lacks 1 of the 2 joints of the motion's skeleton "
            "(layers[0]'s): 'a'");
}

}  // namespace
}  // namespace armature
