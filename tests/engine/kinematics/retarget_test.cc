// Retargeting (kinematics/retarget.h): bones point where the source's point
// (after one yaw) across T-pose and A-pose rests, other joint frames, other
// names and centimetres → metres; the hips at the leg-length ratio; CMU 01_01
// onto the demo character and RobotExpressive (../shared/data, skipped when
// absent), with and without feet.
#include <cmath>
#include <fstream>
#include <iterator>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/body_part_map.h"
#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/demo_walk.h"
#include "armature/engine/io/gltf/gltf.h"
#include "armature/engine/kinematics/fk.h"
#include "armature/engine/kinematics/retarget/retarget.h"
#include "../testing/exact_clip.h"

namespace armature {
namespace {

using Eigen::Quaterniond;
using Eigen::Vector3d;

std::vector<Vector3d> Positions(const Clip& clip, double t) {
  const Skeleton& s = *clip.skeleton;
  std::vector<Trs> local(s.size());
  std::vector<Eigen::Affine3d> world(s.size());
  EXPECT_TRUE(SampleClip(clip, t, {}, local).ok());
  ComputeWorld(s, local, world);
  std::vector<Vector3d> out;
  for (const auto& w : world) out.push_back(w.translation());
  return out;
}

std::vector<Vector3d> RestPositions(const Skeleton& s) {
  std::vector<Eigen::Affine3d> world(s.size());
  ComputeWorld(s, s.rest, world);
  std::vector<Vector3d> out;
  for (const auto& w : world) out.push_back(w.translation());
  return out;
}

// The yaw turning the source's left−right thigh line onto the target's, from the rest poses.
Quaterniond ThighYaw(const Skeleton& s, const Skeleton& t, const BodyPartMap& map) {
  const auto ps = RestPositions(s), pt = RestPositions(t);
  Vector3d a =
      ps[static_cast<size_t>(map.source_parts.legs[0].upper)] - ps[static_cast<size_t>(map.source_parts.legs[1].upper)];
  Vector3d b =
      pt[static_cast<size_t>(map.target_parts.legs[0].upper)] - pt[static_cast<size_t>(map.target_parts.legs[1].upper)];
  a.y() = b.y() = 0;
  return Quaterniond(Eigen::AngleAxisd(std::atan2(a.cross(b).y(), a.dot(b)), Vector3d::UnitY()));
}

struct Bone {
  int source_from, source_to, target_from, target_to;
};

// The limb bones (upper arm, forearm, thigh, shin) and the spine to the head, by body part.
std::vector<Bone> LimbAndSpineBones(const BodyPartMap& map) {
  const BodyParts& s = map.source_parts;
  const BodyParts& t = map.target_parts;
  std::vector<Bone> bones;
  for (size_t side = 0; side < 2; ++side) {
    for (const auto* limb : {&s.arms[side], &s.legs[side]}) {
      const LimbJoints& tl = limb == &s.arms[side] ? t.arms[side] : t.legs[side];
      bones.push_back({limb->upper, limb->lower, tl.upper, tl.lower});
      bones.push_back({limb->lower, limb->end, tl.lower, tl.end});
    }
  }
  // Spine: every mapped target spine joint to the next mapped one up to the head.
  std::vector<int> chain_t = {t.hips};
  chain_t.insert(chain_t.end(), t.spine.begin(), t.spine.end());
  chain_t.push_back(t.neck);
  chain_t.push_back(t.head);
  std::vector<std::pair<int, int>> mapped;  // (source, target)
  for (int j : chain_t)
    for (const JointPairIndex& p : map.pairs)
      if (p.target == j) mapped.push_back({p.source, p.target});
  for (size_t i = 0; i + 1 < mapped.size(); ++i)
    bones.push_back({mapped[i].first, mapped[i + 1].first, mapped[i].second, mapped[i + 1].second});
  return bones;
}

double MaxBoneAngleDegrees(const Clip& source, const Clip& target, const std::vector<Bone>& bones,
                           const Quaterniond& yaw, int samples) {
  double worst = 0;
  for (int i = 0; i < samples; ++i) {
    const double t = source.duration * (i + 0.5) / samples;
    const auto ps = Positions(source, t), pt = Positions(target, t);
    for (const Bone& b : bones) {
      const Vector3d ds = yaw * (ps[static_cast<size_t>(b.source_to)] - ps[static_cast<size_t>(b.source_from)]);
      const Vector3d dt = pt[static_cast<size_t>(b.target_to)] - pt[static_cast<size_t>(b.target_from)];
      const double angle = std::atan2(ds.cross(dt).norm(), ds.dot(dt)) * 180 / std::numbers::pi;
      worst = std::max(worst, angle);
    }
  }
  return worst;
}

// The demo walk's skeleton renamed mixamo-style, turned to face −Z, in metres,
// its arms raised to a T-pose, every joint frame turned at random.
std::shared_ptr<Skeleton> TurnedRenamedTPose(const Skeleton& s) {
  const std::vector<std::pair<std::string, std::string>> names = {
      {"Hips", "Hips"},           {"LeftHip", "LeftUpLeg"},      {"LeftKnee", "LeftLeg"},
      {"LeftAnkle", "LeftFoot"},  {"LeftToe", "LeftToeBase"},    {"RightHip", "RightUpLeg"},
      {"RightKnee", "RightLeg"},  {"RightAnkle", "RightFoot"},   {"RightToe", "RightToeBase"},
      {"Spine", "Spine"},         {"Chest", "Spine1"},           {"Neck", "Neck"},
      {"Head", "Head"},           {"LeftShoulder", "LeftArm"},   {"LeftElbow", "LeftForeArm"},
      {"LeftWrist", "LeftHand"},  {"RightShoulder", "RightArm"}, {"RightElbow", "RightForeArm"},
      {"RightWrist", "RightHand"}};
  std::vector<Vector3d> p = RestPositions(s);
  for (const char* side : {"Left", "Right"}) {
    const int shoulder = s.Find(std::string(side) + "Shoulder");
    const double sign = std::string(side) == "Left" ? 1 : -1;
    const Quaterniond raise(Eigen::AngleAxisd(sign * std::numbers::pi / 2, Vector3d::UnitZ()));
    for (const char* part : {"Elbow", "Wrist"}) {
      const size_t j = static_cast<size_t>(s.Find(std::string(side) + part));
      p[j] = p[static_cast<size_t>(shoulder)] + raise * (p[j] - p[static_cast<size_t>(shoulder)]);
    }
  }
  const Quaterniond turn(Eigen::AngleAxisd(std::numbers::pi, Vector3d::UnitY()));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Quaterniond> frame(s.size());
  auto t = std::make_shared<Skeleton>();
  for (size_t j = 0; j < s.size(); ++j) {
    frame[j] = Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
    const Vector3d at = 0.01 * (turn * p[j]) + Vector3d(0, 0.05, 0);
    const int parent = s.parents[j];
    Trs rest;
    if (parent < 0) {
      rest.translation = at;
      rest.rotation = frame[j];
    } else {
      const Vector3d parent_at = 0.01 * (turn * p[static_cast<size_t>(parent)]) + Vector3d(0, 0.05, 0);
      rest.translation = frame[static_cast<size_t>(parent)].conjugate() * (at - parent_at);
      rest.rotation = frame[static_cast<size_t>(parent)].conjugate() * frame[j];
    }
    std::string name = s.names[j];
    for (const auto& [from, to] : names)
      if (from == name) name = "mixamorig:" + to;
    t->names.push_back(name);
    t->parents.push_back(parent);
    t->rest.push_back(rest);
  }
  t->channels.resize(s.size());
  t->end_sites.resize(s.size());
  return t;
}

TEST(Retarget, BonesFollowTheSourceAcrossPosesFramesNamesFacingAndUnits) {
  const BvhData walk = MakeDemoWalk();
  const Clip& source = *walk.clip;
  const auto target = TurnedRenamedTPose(*source.skeleton);
  ASSERT_TRUE(target->Validate().ok());
  auto map = MapJointsByBodyParts(*source.skeleton, *target, {});
  ASSERT_TRUE(map.ok()) << map.status().message();
  EXPECT_EQ(map->pairs.size(), target->size());
  auto result = RetargetClip(*test_util::ExactClip(source), *target, *map);
  ASSERT_TRUE(result.ok()) << result.status().message();
  EXPECT_NEAR(result->scale, 0.01, 1e-12);
  const Quaterniond yaw = ThighYaw(*source.skeleton, *target, *map);
  EXPECT_NEAR(std::abs(yaw.w()), 0.0, 1e-9);  // half a turn
  const double worst = MaxBoneAngleDegrees(source, result->clip, LimbAndSpineBones(*map), yaw, 10);
  EXPECT_LT(worst, 1e-4) << "degrees";
  // The hips (thighs' midpoint) at the source's, scaled and turned.
  for (double t : {0.1, 0.4, 0.77}) {
    const auto ps = Positions(source, t), pt = Positions(result->clip, t);
    const auto& sl = map->source_parts.legs;
    const auto& tl = map->target_parts.legs;
    const Vector3d hs = 0.5 * (ps[static_cast<size_t>(sl[0].upper)] + ps[static_cast<size_t>(sl[1].upper)]);
    const Vector3d ht = 0.5 * (pt[static_cast<size_t>(tl[0].upper)] + pt[static_cast<size_t>(tl[1].upper)]);
    EXPECT_LT((ht - 0.01 * (yaw * hs)).norm(), 1e-9);
  }
  EXPECT_EQ(result->clip.skeleton->names, target->names);
}

TEST(Retarget, RefusesOutputOverItsBoundsAndBadFrameTimes) {
  const BvhData walk = MakeDemoWalk();
  const Skeleton& skeleton = *walk.clip->skeleton;
  auto map = MapJointsByBodyParts(skeleton, skeleton, {});
  ASSERT_TRUE(map.ok());
  RetargetOptions options;
  options.max_keys = 100;
  auto keys = RetargetClip(*test_util::ExactClip(walk.clip), skeleton, *map, options);
  EXPECT_EQ(keys.status().code(), StatusCode::kResourceExhausted);
  EXPECT_NE(keys.status().message().find("over 100 keys"), std::string::npos) << keys.status().message();
  options = {};
  options.frame_time = 1e-9;
  EXPECT_EQ(RetargetClip(*test_util::ExactClip(walk.clip), skeleton, *map, options).status().code(),
            StatusCode::kResourceExhausted);
  options.frame_time = -1;
  EXPECT_EQ(RetargetClip(*test_util::ExactClip(walk.clip), skeleton, *map, options).status().code(),
            StatusCode::kInvalidArgument);
  // Onto itself: every joint back where it was.
  auto same = RetargetClip(*test_util::ExactClip(walk.clip), skeleton, *map);
  ASSERT_TRUE(same.ok()) << same.status().message();
  for (double t : {0.0, 0.3, 1.1}) {
    const auto a = Positions(*walk.clip, t), b = Positions(same->clip, t);
    for (size_t j = 0; j < a.size(); ++j) EXPECT_LT((a[j] - b[j]).norm(), 1e-6) << skeleton.names[j] << " t=" << t;
  }
}

const Clip* Cmu() {
  static std::shared_ptr<const Clip> clip = [] {
    std::ifstream in(ARMATURE_SHARED_DATA "/bvh/cmu_01_01.bvh");
    if (!in) return std::shared_ptr<const Clip>();
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto bvh = ParseBvh(text);
    EXPECT_TRUE(bvh.ok()) << bvh.status().message();
    return bvh.ok() ? std::shared_ptr<const Clip>(bvh->clip) : nullptr;
  }();
  return clip.get();
}

std::shared_ptr<const Skeleton> Robot() {
  std::ifstream in(ARMATURE_SHARED_DATA "/gltf/RobotExpressive/RobotExpressive.glb", std::ios::binary);
  if (!in) return nullptr;
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto asset = ParseGltf(bytes, true, "robot");
  EXPECT_TRUE(asset.ok()) << asset.status().message();
  return asset.ok() ? asset->skeletons.at(0).skeleton : nullptr;
}

double LegLength(const std::vector<Vector3d>& p, const LimbJoints& leg) {
  return (p[static_cast<size_t>(leg.lower)] - p[static_cast<size_t>(leg.upper)]).norm() +
         (p[static_cast<size_t>(leg.end)] - p[static_cast<size_t>(leg.lower)]).norm();
}

// The farthest the target's foot strays, as a fraction of its leg length, over
// stretches where the source's foot is planted: within 5 % of the leg length
// of its lowest and slower than 15 % of the leg length per second, for at
// least 5 of the 120 Hz frames.
double MaxPlantedFootDrift(const Clip& source, const Clip& target, const BodyPartMap& map, size_t* stretches) {
  const double dt = source.frame_time;
  const size_t n = static_cast<size_t>(source.duration / dt) + 1;
  double worst = 0;
  *stretches = 0;
  for (size_t side = 0; side < 2; ++side) {
    const LimbJoints& sl = map.source_parts.legs[side];
    const LimbJoints& tl = map.target_parts.legs[side];
    std::vector<Vector3d> source_foot, target_foot;
    double ls = 0, lt = 0;
    for (size_t i = 0; i < n; ++i) {
      const auto ps = Positions(source, static_cast<double>(i) * dt);
      const auto pt = Positions(target, static_cast<double>(i) * dt);
      source_foot.push_back(ps[static_cast<size_t>(sl.end)]);
      target_foot.push_back(pt[static_cast<size_t>(tl.end)]);
      if (i == 0) {
        ls = LegLength(ps, sl);
        lt = LegLength(pt, tl);
      }
    }
    double ground = source_foot[0].y();
    for (const auto& p : source_foot) ground = std::min(ground, p.y());
    std::vector<bool> planted(n);
    for (size_t i = 1; i + 1 < n; ++i)
      planted[i] = source_foot[i].y() - ground < 0.05 * ls &&
                   (source_foot[i + 1] - source_foot[i - 1]).norm() / (2 * dt) < 0.15 * ls;
    for (size_t i = 0; i < n;) {
      size_t end = i;
      while (end < n && planted[end]) ++end;
      if (end - i >= 5) {
        ++*stretches;
        for (size_t a = i; a < end; ++a)
          for (size_t b = a + 1; b < end; ++b) worst = std::max(worst, (target_foot[a] - target_foot[b]).norm() / lt);
      }
      i = std::max(end, i + 1);
    }
  }
  return worst;
}

void CheckCmuOnto(const Skeleton& target, bool feet) {
  const Clip& source = *Cmu();
  auto map = MapJointsByBodyParts(*source.skeleton, target, {});
  ASSERT_TRUE(map.ok()) << map.status().message();
  RetargetOptions options;
  options.feet = feet;
  auto result = RetargetClip(*test_util::ExactClip(source), target, *map, options);
  ASSERT_TRUE(result.ok()) << result.status().message();
  if (!feet) {
    const double worst = MaxBoneAngleDegrees(source, result->clip, LimbAndSpineBones(*map),
                                             ThighYaw(*source.skeleton, target, *map), 10);
    std::printf("max bone angle %.4f degrees\n", worst);
    EXPECT_LT(worst, 1.0);
  } else {
    size_t stretches = 0;
    const double drift = MaxPlantedFootDrift(source, result->clip, *map, &stretches);
    std::printf("planted foot drift %.5f of the leg length over %zu stretches (%zu frames pinned)\n", drift, stretches,
                result->planted_frames);
    EXPECT_GT(stretches, 0u);
    EXPECT_LT(drift, 0.01);
  }
}

TEST(Retarget, CmuOntoTheDemoCharacter) {
  if (!Cmu()) GTEST_SKIP() << "../shared/data/bvh/cmu_01_01.bvh is absent";
  CheckCmuOnto(*MakeDemoWalk().clip->skeleton, false);
  CheckCmuOnto(*MakeDemoWalk().clip->skeleton, true);
}

TEST(Retarget, CmuOntoRobotExpressive) {
  const auto robot = Robot();
  if (!Cmu() || !robot) GTEST_SKIP() << "../shared/data (CMU 01_01, RobotExpressive) is absent";
  CheckCmuOnto(*robot, false);
  CheckCmuOnto(*robot, true);
}

}  // namespace
}  // namespace armature
