#include "armature/engine/io/demo_walk.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "armature/engine/kinematics/fk.h"
#include "armature/engine/math/rotation.h"

namespace armature {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// A keyed joint pose at a phase of the cycle (0 = left heel strike), in
// anatomical degrees: flexion (positive = the usual bending direction),
// yaw about the vertical and abduction (positive = away from the body).
struct PoseKey {
  double phase;
  double flex;
  double yaw = 0;
  double abduct = 0;
};

// How a joint's flexion maps onto a rotation about its X axis: with Y up,
// facing +Z, +X rotation swings a downward bone backwards, so hip, ankle,
// toe, shoulder and elbow flexion are negative and knee flexion positive.
struct JointCurve {
  const char* joint;
  double flex_sign;
  std::vector<PoseKey> keys;
  bool mirrored;  // also drives the Right* joint half a cycle later
};

const std::vector<JointCurve>& Curves() {
  static const std::vector<JointCurve> curves = {
      {"Hips", 1, {{0.00, 0, -5}, {0.25, 0, 0}, {0.50, 0, 5}, {0.75, 0, 0}}, false},
      {"Spine", 1, {{0.00, 3, 2}, {0.25, 3, 0}, {0.50, 3, -2}, {0.75, 3, 0}}, false},
      {"Chest", 1, {{0.00, 0, 6}, {0.25, 0, 0}, {0.50, 0, -6}, {0.75, 0, 0}}, false},
      {"Neck", 1, {{0.00, 0, -3}, {0.25, 0, 0}, {0.50, 0, 3}, {0.75, 0, 0}}, false},
      {"Head", 1, {{0.00, -3}, {0.50, -3}}, false},
      // The hip's yaw undoes the pelvis yaw (≈ −5°·cos 2π·phase) so the
      // stance foot does not twist with the pelvis.
      {"LeftHip",
       -1,
       {{0.00, 25, 5},
        {0.15, 20, 2.94},
        {0.30, 6, -1.55},
        {0.50, -10, -5},
        {0.60, -6, -4.05},
        {0.75, 18, 0},
        {0.88, 27, 3.65}},
       true},
      {"LeftKnee",
       1,
       {{0.00, 3}, {0.12, 17}, {0.35, 5}, {0.50, 8}, {0.62, 40}, {0.72, 62}, {0.85, 32}, {0.95, 4}},
       true},
      {"LeftAnkle", -1, {{0.00, 0}, {0.08, -6}, {0.35, 8}, {0.48, 10}, {0.62, -18}, {0.75, 0}, {0.90, 2}}, true},
      {"LeftToe", -1, {{0.00, 0}, {0.40, 0}, {0.55, 22}, {0.65, 10}, {0.75, 0}}, true},
      {"LeftShoulder", -1, {{0.00, -15, 0, 6}, {0.25, 0, 0, 6}, {0.50, 15, 0, 6}, {0.75, 0, 0, 6}}, true},
      {"LeftElbow", -1, {{0.00, 10}, {0.25, 16}, {0.50, 25}, {0.75, 16}}, true},
  };
  return curves;
}

// Root height keys: a bob that is lowest at double support, highest at
// mid-stance. (No sideways sway: with legs that do not adduct it would drag
// the stance foot sideways.)
struct RootKey {
  double phase, bob;
};
constexpr RootKey kRootKeys[] = {{0.00, -1.5}, {0.25, 1.5}, {0.50, -1.5}, {0.75, 1.5}};

std::shared_ptr<Skeleton> MakeSkeleton() {
  auto sk = std::make_shared<Skeleton>();
  auto add = [&](const char* name, int parent, Eigen::Vector3d offset, std::vector<Channel> channels) {
    sk->names.emplace_back(name);
    sk->parents.push_back(parent);
    Trs rest;
    rest.translation = offset;
    sk->rest.push_back(rest);
    sk->channels.push_back(std::move(channels));
    sk->end_sites.emplace_back();
    return static_cast<int>(sk->names.size()) - 1;
  };
  const std::vector<Channel> zxy = {Channel::kZrotation, Channel::kXrotation, Channel::kYrotation};
  const int hips = add("Hips", -1, {0, 0, 0},
                       {Channel::kXposition, Channel::kYposition, Channel::kZposition, Channel::kZrotation,
                        Channel::kXrotation, Channel::kYrotation});
  // Depth-first order (legs, then spine, neck, head, arms), as a BVH file
  // lists joints, so write → read keeps the indices.
  for (double side : {1.0, -1.0}) {  // left = +X
    const std::string s = side > 0 ? "Left" : "Right";
    const int hip = add((s + "Hip").c_str(), hips, {side * 9, -5, 0}, zxy);
    const int knee = add((s + "Knee").c_str(), hip, {0, -42, 0}, zxy);
    const int ankle = add((s + "Ankle").c_str(), knee, {0, -42, 0}, zxy);
    const int toe = add((s + "Toe").c_str(), ankle, {0, -6, 12}, zxy);
    sk->end_sites[static_cast<size_t>(toe)] = Eigen::Vector3d(0, 0, 6);
  }
  const int spine = add("Spine", hips, {0, 10, 0}, zxy);
  const int chest = add("Chest", spine, {0, 15, 0}, zxy);
  const int neck = add("Neck", chest, {0, 20, 0}, zxy);
  const int head = add("Head", neck, {0, 10, 0}, zxy);
  sk->end_sites[static_cast<size_t>(head)] = Eigen::Vector3d(0, 18, 0);
  for (double side : {1.0, -1.0}) {
    const std::string s = side > 0 ? "Left" : "Right";
    const int shoulder = add((s + "Shoulder").c_str(), chest, {side * 17, 17, 0}, zxy);
    const int elbow = add((s + "Elbow").c_str(), shoulder, {0, -28, 0}, zxy);
    const int wrist = add((s + "Wrist").c_str(), elbow, {0, -26, 0}, zxy);
    sk->end_sites[static_cast<size_t>(wrist)] = Eigen::Vector3d(0, -18, 0);
  }
  return sk;
}

// Key times of one cycle's phases repeated from one cycle before the clip to
// one after it, so CUBIC sampling has true neighbours at both ends and the
// clip's last frame matches its first.
template <class Key, class Emit>
void RepeatOverCycles(std::vector<Key> keys, double phase_shift, const Emit& emit) {
  for (Key& k : keys) k.phase = std::fmod(k.phase + phase_shift, 1.0);
  std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) { return a.phase < b.phase; });
  for (int c = -1; c <= kDemoWalkCycles; ++c)
    for (const Key& k : keys) emit((c + k.phase) * kDemoWalkCycleSeconds, k);
}

// `mirror` is −1 for the right side: reflecting across the body's midplane
// keeps rotations about X and negates those about Y and Z.
QuatTrack RotationKeys(const JointCurve& curve, double phase_shift, double mirror) {
  QuatTrack track;
  track.interpolation = Interpolation::kCubic;
  const Axis axes[3] = {Axis::kY, Axis::kX, Axis::kZ};
  RepeatOverCycles(curve.keys, phase_shift, [&](double t, const PoseKey& k) {
    const double angles[3] = {mirror * k.yaw * kDegree, curve.flex_sign * k.flex * kDegree,
                              mirror * k.abduct * kDegree};
    track.times.push_back(t);
    track.values.push_back(EulerToQuaternion(axes, angles));
  });
  return track;
}

Vec3Track RootTranslationKeys() {
  Vec3Track track;
  track.interpolation = Interpolation::kCubic;
  RepeatOverCycles(std::vector<RootKey>(std::begin(kRootKeys), std::end(kRootKeys)), 0.0,
                   [&](double t, const RootKey& k) {
                     track.times.push_back(t);
                     track.values.emplace_back(0.0, kDemoWalkHipHeight + k.bob, kDemoWalkSpeed * t);
                   });
  return track;
}

// The ankle and toe are keyed as angles, blind to the pelvis height: in late
// stance and at toe-off (hip extended, pelvis low at double support) the
// keys alone put the ball of the foot up to 3.5 cm and the toe tip 4.5 cm
// below the floor (y = 0). Each sampled frame, an ankle whose ball is below
// the floor dorsiflexes (toes up, about its X axis) until the ball is on it,
// and that toe then lies flat (its tip on the floor too); a toe tip still
// below the floor is lifted to it. Feet above the floor keep their keyed
// angles. The same correction on both sides keeps the right the mirrored left.
class FloorContact {
 public:
  explicit FloorContact(const Skeleton& sk) : sk_(sk), world_(sk.size()) {}

  void Apply(std::vector<Trs>& pose) {
    for (const char* side : {"Left", "Right"}) {
      const int ankle = sk_.Find(std::string(side) + "Ankle"), toe = sk_.Find(std::string(side) + "Toe");
      const Eigen::Vector3d ball = Eigen::Vector3d::Zero(), tip = *sk_.end_sites[static_cast<size_t>(toe)];
      if (Height(pose, ankle, 0, ball, toe) < 0) {
        PutOnFloor(pose, ankle, 0, ball, toe);
        PutOnFloor(pose, toe, -kMostTurn, tip, toe);
      } else if (Height(pose, toe, 0, tip, toe) < 0) {
        PutOnFloor(pose, toe, 0, tip, toe);
      }
    }
  }

 private:
  static constexpr double kMostTurn = 60 * kDegree;
  // "On the floor" is this high (cm): frames are linearly interpolated, and
  // at toe-off, where the toe turns fast, halfway between two frames on the
  // floor the tip would dip 0.6 cm below it.
  static constexpr double kClearance = 0.5;

  // Height above kClearance of `point` (in joint `frame`'s space) with `joint` turned toes-up
  // by `angle` from its pose; flexion of the ankle and toe is a negative X
  // rotation (see JointCurve).
  double Height(const std::vector<Trs>& pose, int joint, double angle, const Eigen::Vector3d& point, int frame) {
    turned_ = pose;
    Eigen::Quaterniond& rotation = turned_[static_cast<size_t>(joint)].rotation;
    rotation = rotation * Eigen::AngleAxisd(-angle, Eigen::Vector3d::UnitX());
    ComputeWorld(sk_, turned_, world_);
    return (world_[static_cast<size_t>(frame)] * point).y() - kClearance;
  }

  // Turns `joint` toes-up by the angle in [lowest, kMostTurn] (bisection:
  // the height grows with it) that puts `point` on the floor.
  void PutOnFloor(std::vector<Trs>& pose, int joint, double lowest, const Eigen::Vector3d& point, int frame) {
    double below = lowest, above = kMostTurn;
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (below + above);
      (Height(pose, joint, mid, point, frame) < 0 ? below : above) = mid;
    }
    Eigen::Quaterniond& rotation = pose[static_cast<size_t>(joint)].rotation;
    rotation = rotation * Eigen::AngleAxisd(-above, Eigen::Vector3d::UnitX());
  }

  const Skeleton& sk_;
  std::vector<Trs> turned_;
  std::vector<Eigen::Affine3d> world_;
};

}  // namespace

BvhData MakeDemoWalk() {
  const std::shared_ptr<const Skeleton> skeleton = MakeSkeleton();
  const Skeleton& sk = *skeleton;

  Clip keyframes;
  keyframes.skeleton = skeleton;
  keyframes.joints.resize(sk.size());
  keyframes.duration = kDemoWalkCycles * kDemoWalkCycleSeconds;
  keyframes.default_interpolation = Interpolation::kCubic;
  keyframes.joints[0].translation = RootTranslationKeys();
  for (const JointCurve& curve : Curves()) {
    keyframes.joints[static_cast<size_t>(sk.Find(curve.joint))].rotation = RotationKeys(curve, 0.0, 1.0);
    if (curve.mirrored) {
      const std::string right = "Right" + std::string(curve.joint).substr(4);  // "Left…" → "Right…"
      keyframes.joints[static_cast<size_t>(sk.Find(right))].rotation = RotationKeys(curve, 0.5, -1.0);
    }
  }

  auto clip = std::make_shared<Clip>();
  clip->skeleton = skeleton;
  clip->joints.resize(sk.size());
  clip->frame_time = kDemoWalkFrameTime;
  clip->frame_count = static_cast<size_t>(std::lround(keyframes.duration / kDemoWalkFrameTime)) + 1;
  clip->duration = static_cast<double>(clip->frame_count - 1) * kDemoWalkFrameTime;
  clip->default_interpolation = Interpolation::kLinear;

  SampleOptions cubic;
  cubic.interpolation = Interpolation::kCubic;
  std::vector<Trs> pose(sk.size());
  FloorContact floor(sk);
  for (size_t f = 0; f < clip->frame_count; ++f) {
    const double t = static_cast<double>(f) * kDemoWalkFrameTime;
    // The keyframe clip is built here and always valid.
    (void)SampleClip(keyframes, t, cubic, pose);
    floor.Apply(pose);
    for (size_t j = 0; j < sk.size(); ++j) {
      JointTrack& track = clip->joints[j];
      track.rotation.times.push_back(t);
      track.rotation.values.push_back(pose[j].rotation);
      if (sk.parents[j] < 0) {
        track.translation.times.push_back(t);
        track.translation.values.push_back(pose[j].translation);
      }
    }
  }
  return BvhData{skeleton, clip, {}};
}

}  // namespace armature
