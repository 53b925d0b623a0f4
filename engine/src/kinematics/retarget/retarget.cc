#include "armature/engine/kinematics/retarget/retarget.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/kinematics/fk.h"
#include "armature/engine/kinematics/ik.h"
#include "armature/engine/math/rotation.h"
#include "retarget_feet.h"

namespace armature {
namespace {

using Eigen::Quaterniond;
using Eigen::Vector3d;

bool IsAncestor(const Skeleton& s, int ancestor, int joint) {
  for (int j = joint; j >= 0; j = s.parents[static_cast<size_t>(j)])
    if (j == ancestor) return true;
  return false;
}

int RootOf(const Skeleton& s, int joint) {
  while (s.parents[static_cast<size_t>(joint)] >= 0) joint = s.parents[static_cast<size_t>(joint)];
  return joint;
}

// A world rest pose: positions and rotations.
struct WorldPose {
  std::vector<Eigen::Affine3d> world;
  std::vector<Quaterniond> rotation;
  Vector3d At(int j) const { return world[static_cast<size_t>(j)].translation(); }
};

WorldPose RestWorld(const Skeleton& s) {
  WorldPose w;
  w.world.resize(s.size());
  w.rotation.resize(s.size());
  ComputeWorld(s, s.rest, w.world, w.rotation);
  return w;
}

double LegLength(const WorldPose& w, const LimbJoints& leg) {
  if (leg.upper < 0 || leg.lower < 0 || leg.end < 0) return 0;
  return (w.At(leg.lower) - w.At(leg.upper)).norm() + (w.At(leg.end) - w.At(leg.lower)).norm();
}

bool HasLegs(const BodyParts& p) {
  return p.legs[0].upper >= 0 && p.legs[1].upper >= 0 && p.legs[0].lower >= 0 && p.legs[1].lower >= 0 &&
         p.legs[0].end >= 0 && p.legs[1].end >= 0;
}

Vector3d Horizontal(Vector3d v) {
  v.y() = 0;
  return v;
}

// The rotation about +Y taking the horizontal part of `from` onto that of `to`.
Quaterniond YawBetween(const Vector3d& from, const Vector3d& to) {
  const Vector3d a = Horizontal(from), b = Horizontal(to);
  if (a.norm() < 1e-12 || b.norm() < 1e-12) return Quaterniond::Identity();
  const double angle = std::atan2(a.cross(b).y(), a.dot(b));
  return Quaterniond(Eigen::AngleAxisd(angle, Vector3d::UnitY()));
}

// What stays the same for every frame.
struct Plan {
  std::vector<int> source_of;              // per target joint
  std::vector<int> target_of;              // per source joint
  std::vector<int> tail;                   // per target joint: the mapped joint its bone points to, or -1
  std::vector<Quaterniond> align;          // C per target joint
  std::vector<Vector3d> source_rest_bone;  // Rs0-frame bone vector (world, rest) per target joint
  std::vector<int> carrier;                // per target joint: the joint carrying it rigidly, or -1
  std::vector<int> carried;                // target joints with a carrier, in source order
  Quaterniond yaw = Quaterniond::Identity();
  double scale = 1.0;
  int source_left_thigh = -1, source_right_thigh = -1, target_left_thigh = -1, target_right_thigh = -1;
  int source_pelvis = -1, target_pelvis = -1;  // when the legs are not both known
  int moved_root = -1;                         // the target root that is translated
};

Status ValidatePairs(const CompressedClip& source, const Skeleton& target, const BodyPartMap& map, Plan& plan) {
  const Skeleton& s = *source.skeleton;
  plan.source_of.assign(target.size(), -1);
  plan.target_of.assign(s.size(), -1);
  for (size_t i = 0; i < map.pairs.size(); ++i) {
    const JointPairIndex p = map.pairs[i];
    if (p.source < 0 || static_cast<size_t>(p.source) >= s.size() || p.target < 0 ||
        static_cast<size_t>(p.target) >= target.size())
      return Status::InvalidArgument("pairs[" + std::to_string(i) + "]: joint index out of range");
    if (plan.source_of[static_cast<size_t>(p.target)] >= 0)
      return Status::InvalidArgument("pairs[" + std::to_string(i) + "]: target joint '" +
                                     target.names[static_cast<size_t>(p.target)] + "' is mapped twice");
    if (plan.target_of[static_cast<size_t>(p.source)] >= 0)
      return Status::InvalidArgument("pairs[" + std::to_string(i) + "]: source joint '" +
                                     s.names[static_cast<size_t>(p.source)] + "' is mapped twice");
    plan.source_of[static_cast<size_t>(p.target)] = p.source;
    plan.target_of[static_cast<size_t>(p.source)] = p.target;
  }
  return Status::Ok();
}

// The nearest mapped strict ancestor of source joint `j`, or -1.
int MappedSourceAncestor(const Skeleton& s, const Plan& plan, int j) {
  for (int a = s.parents[static_cast<size_t>(j)]; a >= 0; a = s.parents[static_cast<size_t>(a)])
    if (plan.target_of[static_cast<size_t>(a)] >= 0) return a;
  return -1;
}

void PlanBones(const Skeleton& s, const Skeleton& t, const WorldPose& s0, const WorldPose& t0, Plan& plan) {
  const size_t n = t.size();
  plan.tail.assign(n, -1);
  plan.align.assign(n, Quaterniond::Identity());
  plan.source_rest_bone.assign(n, Vector3d::Zero());
  plan.carrier.assign(n, -1);
  std::vector<int> anchor(s.size(), -1);
  for (size_t j = 0; j < s.size(); ++j)
    if (plan.target_of[j] >= 0) anchor[j] = MappedSourceAncestor(s, plan, static_cast<int>(j));
  // Tails: the mapped child (through unmapped joints) that continues the bone most straight.
  std::vector<double> best(n, -2.0);
  for (size_t sk = 0; sk < s.size(); ++sk) {
    const int k = plan.target_of[sk];
    const int sj = anchor[sk];
    if (k < 0 || sj < 0) continue;
    const int j = plan.target_of[static_cast<size_t>(sj)];
    const Vector3d bone = s0.At(static_cast<int>(sk)) - s0.At(sj);
    const Vector3d target_bone = t0.At(k) - t0.At(j);
    if (bone.norm() < 1e-9 || target_bone.norm() < 1e-9) continue;
    const int grand = anchor[static_cast<size_t>(sj)];
    Vector3d incoming = grand >= 0 ? Vector3d(s0.At(sj) - s0.At(grand)) : Vector3d::UnitY();
    if (incoming.norm() < 1e-9) incoming = Vector3d::UnitY();
    const double score = bone.normalized().dot(incoming.normalized());
    if (score > best[static_cast<size_t>(j)]) {
      best[static_cast<size_t>(j)] = score;
      plan.tail[static_cast<size_t>(j)] = k;
    }
  }
  for (size_t j = 0; j < n; ++j) {
    const int sj = plan.source_of[j];
    if (sj < 0) continue;
    // A target joint whose source hangs from another mapped joint than its own target parent
    // chain does (RobotExpressive's FootL hangs from the armature's root, CMU's LeftFoot from
    // the shin) is carried by that joint's counterpart.
    if (anchor[static_cast<size_t>(sj)] >= 0) {
      const int c = plan.target_of[static_cast<size_t>(anchor[static_cast<size_t>(sj)])];
      if (!IsAncestor(t, c, static_cast<int>(j)) && !IsAncestor(t, static_cast<int>(j), c)) {
        plan.carrier[j] = c;
        plan.carried.push_back(static_cast<int>(j));
      }
    }
    const int k = plan.tail[j];
    if (k < 0) continue;
    const Vector3d source_bone = s0.At(plan.source_of[static_cast<size_t>(k)]) - s0.At(sj);
    plan.source_rest_bone[j] = source_bone;
    const Vector3d target_bone = t0.At(k) - t0.At(static_cast<int>(j));
    plan.align[j] = Quaterniond::FromTwoVectors(target_bone, plan.yaw * source_bone);
  }
  std::sort(plan.carried.begin(), plan.carried.end(), [&](int a, int b) {
    return plan.source_of[static_cast<size_t>(a)] < plan.source_of[static_cast<size_t>(b)];
  });
}

// Per-frame scratch, allocated once.
struct Frame {
  std::vector<Trs> source_local;
  WorldPose source;
  std::vector<Trs> local;
  std::vector<Quaterniond> rotation;  // target world rotations
  std::vector<Eigen::Affine3d> world;
  std::vector<unsigned char> dirty;
};

void UpdateWorldFrom(const Skeleton& t, int from, Frame& f) {
  std::fill(f.dirty.begin(), f.dirty.end(), 0);
  f.dirty[static_cast<size_t>(from)] = 1;
  for (size_t k = static_cast<size_t>(from); k < t.size(); ++k) {
    const int p = t.parents[k];
    if (k != static_cast<size_t>(from) && (p < 0 || !f.dirty[static_cast<size_t>(p)])) continue;
    f.dirty[k] = 1;
    f.world[k] = p < 0 ? f.local[k].ToAffine() : f.world[static_cast<size_t>(p)] * f.local[k].ToAffine();
  }
}

// Carried joints follow their carrier rigidly from the rest pose.
void PlaceCarried(const Skeleton& t, const WorldPose& t0, const Plan& plan, Frame& f) {
  for (int j : plan.carried) {
    const int c = plan.carrier[static_cast<size_t>(j)];
    const Quaterniond turn = f.rotation[static_cast<size_t>(c)] * t0.rotation[static_cast<size_t>(c)].conjugate();
    const Vector3d at = f.world[static_cast<size_t>(c)].translation() + turn * (t0.At(j) - t0.At(c));
    const int p = t.parents[static_cast<size_t>(j)];
    f.local[static_cast<size_t>(j)].translation = p < 0 ? at : Vector3d(f.world[static_cast<size_t>(p)].inverse() * at);
    UpdateWorldFrom(t, j, f);
  }
}

// Facing and scale from the legs, else the arms' facing and no scale (a warning says so).
void PlanFacingAndScale(const Skeleton& target, const WorldPose& s0, const WorldPose& t0, const BodyParts& sp,
                        const BodyParts& tp, Plan& plan, std::vector<std::string>& warnings) {
  if (HasLegs(sp) && HasLegs(tp)) {
    plan.source_left_thigh = sp.legs[0].upper;
    plan.source_right_thigh = sp.legs[1].upper;
    plan.target_left_thigh = tp.legs[0].upper;
    plan.target_right_thigh = tp.legs[1].upper;
    plan.yaw = YawBetween(s0.At(plan.source_left_thigh) - s0.At(plan.source_right_thigh),
                          t0.At(plan.target_left_thigh) - t0.At(plan.target_right_thigh));
    const double ls = 0.5 * (LegLength(s0, sp.legs[0]) + LegLength(s0, sp.legs[1]));
    const double lt = 0.5 * (LegLength(t0, tp.legs[0]) + LegLength(t0, tp.legs[1]));
    if (ls > 1e-9 && lt > 1e-9) plan.scale = lt / ls;
    plan.moved_root = RootOf(target, plan.target_left_thigh);
    return;
  }
  warnings.push_back("no hip–knee–ankle legs on both skeletons: the root translation is not scaled");
  if (sp.arms[0].upper >= 0 && sp.arms[1].upper >= 0 && tp.arms[0].upper >= 0 && tp.arms[1].upper >= 0)
    plan.yaw = YawBetween(s0.At(sp.arms[0].upper) - s0.At(sp.arms[1].upper),
                          t0.At(tp.arms[0].upper) - t0.At(tp.arms[1].upper));
  plan.source_pelvis = sp.hips >= 0 ? sp.hips : 0;
  plan.target_pelvis = plan.target_of[static_cast<size_t>(plan.source_pelvis)];
  if (plan.target_pelvis >= 0) plan.moved_root = RootOf(target, plan.target_pelvis);
}

// The output's key times: every `dt` from 0, and the source's end.
StatusOr<std::vector<double>> FrameTimes(const CompressedClip& source, double dt, size_t max_frames) {
  const double frames_exact = source.duration / dt;
  if (frames_exact + 2 > static_cast<double>(max_frames))
    return Status::ResourceExhausted("retargeting " + std::to_string(source.duration) + " s at " + std::to_string(dt) +
                                     " s per frame makes more than " + std::to_string(max_frames) + " frames");
  const size_t frames = static_cast<size_t>(std::floor(frames_exact + 1e-9)) + 1;
  std::vector<double> times(frames);
  for (size_t i = 0; i < frames; ++i) times[i] = std::min(static_cast<double>(i) * dt, source.duration);
  if (frames > 1 && times.back() < source.duration - 1e-9) times.push_back(source.duration);
  return times;
}

// Poses the target frame by frame from the sampled source, before the feet.
class FramePoser {
 public:
  FramePoser(const CompressedClip& source, const Skeleton& target, const Plan& plan, const WorldPose& s0,
             const WorldPose& t0)
      : source_(source),
        context_(source),
        s_(*source.skeleton),
        target_(target),
        plan_(plan),
        s0_(s0),
        t0_(t0),
        yaw_inv_(plan.yaw.conjugate()) {
    f_.source_local.resize(s_.size());
    f_.source.world.resize(s_.size());
    f_.source.rotation.resize(s_.size());
    f_.local = target.rest;
    f_.rotation.resize(target.size());
    f_.world.resize(target.size());
    f_.dirty.resize(target.size());
  }

  Frame& frame() { return f_; }

  // The source's local and world pose at `time`.
  Status SampleSource(double time) {
    ARMATURE_RETURN_IF_ERROR((ClipSamplingJob{&source_, time, WrapMode::kClamp, &context_, f_.source_local, {}}.Run()));
    ComputeWorld(s_, f_.source_local, f_.source.world, f_.source.rotation);
    return Status::Ok();
  }

  // One frame retargeted, before the feet: f.local and f.world.
  Status Pose(double time) {
    ARMATURE_RETURN_IF_ERROR(SampleSource(time));
    SetRotations();
    ComputeWorld(target_, f_.local, f_.world);
    PlaceCarried(target_, t0_, plan_, f_);
    MoveRoot();
    return Status::Ok();
  }

 private:
  // World rotations, parents first, and the local rotations they imply.
  void SetRotations() {
    for (size_t j = 0; j < target_.size(); ++j) {
      const int p = target_.parents[j];
      const int sj = plan_.source_of[j];
      Quaterniond r;
      if (sj < 0) {
        r = (p < 0 ? Quaterniond::Identity() : f_.rotation[static_cast<size_t>(p)]) * target_.rest[j].rotation;
      } else {
        const Quaterniond delta =
            f_.source.rotation[static_cast<size_t>(sj)] * s0_.rotation[static_cast<size_t>(sj)].conjugate();
        r = plan_.yaw * delta * yaw_inv_ * plan_.align[j] * t0_.rotation[j];
        if (const int k = plan_.tail[j]; k >= 0) {
          const Vector3d predicted = plan_.yaw * (delta * plan_.source_rest_bone[j]);
          const Vector3d actual =
              plan_.yaw * (f_.source.At(plan_.source_of[static_cast<size_t>(k)]) - f_.source.At(sj));
          if (predicted.norm() > 1e-12 && actual.norm() > 1e-12) r = Quaterniond::FromTwoVectors(predicted, actual) * r;
        }
      }
      f_.rotation[j] = r.normalized();
      f_.local[j].rotation =
          (p < 0 ? f_.rotation[j] : f_.rotation[static_cast<size_t>(p)].conjugate() * f_.rotation[j]).normalized();
    }
  }

  // The root moves the hips onto the scaled, turned source hips.
  void MoveRoot() {
    if (plan_.moved_root < 0) return;
    Vector3d want, have;
    if (plan_.target_left_thigh >= 0) {
      want = 0.5 * (f_.source.At(plan_.source_left_thigh) + f_.source.At(plan_.source_right_thigh));
      have = 0.5 * (f_.world[static_cast<size_t>(plan_.target_left_thigh)].translation() +
                    f_.world[static_cast<size_t>(plan_.target_right_thigh)].translation());
    } else {
      want = f_.source.At(plan_.source_pelvis);
      have = f_.world[static_cast<size_t>(plan_.target_pelvis)].translation();
    }
    const Vector3d shift = plan_.scale * (plan_.yaw * want) - have;
    f_.local[static_cast<size_t>(plan_.moved_root)].translation += shift;
    UpdateWorldFrom(target_, plan_.moved_root, f_);
  }

  const CompressedClip& source_;
  ClipSamplingContext context_;
  const Skeleton& s_;
  const Skeleton& target_;
  const Plan& plan_;
  const WorldPose& s0_;
  const WorldPose& t0_;
  const Quaterniond yaw_inv_;
  Frame f_;
};

// The output clip's frame fields and skeleton; which joints get rotation keys
// (`keyed`). RESOURCE_EXHAUSTED when the keys would pass options.max_keys.
Status StartOutput(const Skeleton& target, const Plan& plan, const FeetPlan& feet, const RetargetOptions& options,
                   std::span<const double> times, double dt, Clip& out, std::vector<unsigned char>& keyed) {
  out.skeleton = std::make_shared<Skeleton>(target);
  out.joints.resize(target.size());
  out.duration = times.back();
  out.frame_time = dt;
  out.frame_count = times.size();
  keyed.assign(target.size(), 0);
  for (size_t j = 0; j < target.size(); ++j)
    keyed[j] = plan.source_of[j] >= 0 || (options.feet && feet.Moves(static_cast<int>(j)));
  const size_t animated = static_cast<size_t>(std::count(keyed.begin(), keyed.end(), 1)) + plan.carried.size() + 1;
  if (animated * times.size() > options.max_keys)
    return Status::ResourceExhausted("retargeting makes " + std::to_string(times.size()) + " frames × " +
                                     std::to_string(animated) + " animated joints, over " +
                                     std::to_string(options.max_keys) + " keys");
  for (int j : plan.carried) out.joints[static_cast<size_t>(j)].translation.times.reserve(times.size());
  return Status::Ok();
}

// Frame `f`'s keys at `time`: rotations of the keyed joints (each in the
// previous key's hemisphere), translations of the moved root and carried joints.
void KeyFrame(const Plan& plan, const std::vector<unsigned char>& keyed, const Frame& f, double time, Clip& out) {
  for (size_t j = 0; j < keyed.size(); ++j) {
    if (!keyed[j]) continue;
    QuatTrack& track = out.joints[j].rotation;
    Quaterniond q = f.local[j].rotation;
    if (!track.values.empty()) q = SameHemisphere(q, track.values.back());
    track.times.push_back(time);
    track.values.push_back(q);
  }
  auto key_translation = [&](int j) {
    Vec3Track& track = out.joints[static_cast<size_t>(j)].translation;
    track.times.push_back(time);
    track.values.push_back(f.local[static_cast<size_t>(j)].translation);
  };
  if (plan.moved_root >= 0) key_translation(plan.moved_root);
  for (int j : plan.carried)
    if (j != plan.moved_root) key_translation(j);
}

// The planted feet's pins: each planted stretch's mean of where the
// retargeted motion puts the foot.
Status SetFootPins(const FeetPlan& feet, std::span<const double> times, FramePoser& poser,
                   std::vector<FootPins>& pins) {
  std::vector<std::vector<Vector3d>> natural(2);
  for (double time : times) {
    ARMATURE_RETURN_IF_ERROR(poser.Pose(time));
    for (size_t side = 0; side < 2; ++side)
      natural[side].push_back(poser.frame().world[static_cast<size_t>(feet.legs[side].effector)] *
                              feet.legs[side].offset);
  }
  SetPins(natural, pins);
  return Status::Ok();
}

// After PinFeet moved the legs: world transforms and rotations again, carried joints after them.
void AfterPinnedFeet(const Skeleton& target, const WorldPose& t0, const Plan& plan, Frame& f) {
  ComputeWorld(target, f.local, f.world);
  for (size_t j = 0; j < target.size(); ++j) {
    const int p = target.parents[j];
    f.rotation[j] = p < 0 ? f.local[j].rotation : f.rotation[static_cast<size_t>(p)] * f.local[j].rotation;
  }
  PlaceCarried(target, t0, plan, f);
}

}  // namespace

StatusOr<RetargetResult> RetargetClip(const CompressedClip& source, const Skeleton& target, const BodyPartMap& map,
                                      const RetargetOptions& options) {
  if (!source.skeleton) return Status::InvalidArgument("source clip has no skeleton");
  ARMATURE_RETURN_IF_ERROR(target.Validate());
  const Skeleton& s = *source.skeleton;
  Plan plan;
  ARMATURE_RETURN_IF_ERROR(ValidatePairs(source, target, map, plan));
  if (!(options.frame_time >= 0) || !std::isfinite(options.frame_time))
    return Status::InvalidArgument("frame_time must be finite and ≥ 0");
  const WorldPose s0 = RestWorld(s), t0 = RestWorld(target);
  const BodyParts& sp = map.source_parts;
  const BodyParts& tp = map.target_parts;
  RetargetResult result;
  PlanFacingAndScale(target, s0, t0, sp, tp, plan, result.warnings);
  PlanBones(s, target, s0, t0, plan);

  FeetPlan feet;
  if (options.feet) ARMATURE_RETURN_IF_ERROR(PlanFeet(target, tp, t0.world, feet));
  const double dt = options.frame_time > 0 ? options.frame_time
                                           : (source.source_frame_time > 0 ? source.source_frame_time : 1.0 / 30);
  ARMATURE_ASSIGN_OR_RETURN(const std::vector<double> times, FrameTimes(source, dt, options.max_frames));

  FramePoser poser(source, target, plan, s0, t0);
  Frame& f = poser.frame();
  std::vector<FootPins> pins;
  if (options.feet) {
    ARMATURE_RETURN_IF_ERROR(FindPlantedFeet(
        times, sp, [&](double time) { return poser.SampleSource(time); }, f.source.world, pins));
    for (const FootPins& p : pins)
      result.planted_frames +=
          static_cast<size_t>(std::count_if(p.stretch.begin(), p.stretch.end(), [](int s) { return s >= 0; }));
  }

  Clip& out = result.clip;
  std::vector<unsigned char> keyed;
  ARMATURE_RETURN_IF_ERROR(StartOutput(target, plan, feet, options, times, dt, out, keyed));
  IkWorkspace ik_workspace;
  IkResult ik_result;
  if (options.feet) ARMATURE_RETURN_IF_ERROR(SetFootPins(feet, times, poser, pins));
  for (size_t fi = 0; fi < times.size(); ++fi) {
    ARMATURE_RETURN_IF_ERROR(poser.Pose(times[fi]));
    if (options.feet) {
      ARMATURE_RETURN_IF_ERROR(
          PinFeet(target, feet, pins, fi, plan.moved_root, f.local, f.world, f.rotation, ik_workspace, ik_result));
      AfterPinnedFeet(target, t0, plan, f);
    }
    KeyFrame(plan, keyed, f, times[fi], out);
  }
  result.scale = plan.scale;
  result.yaw = plan.yaw;
  ARMATURE_RETURN_IF_ERROR(out.Validate());
  return result;
}

}  // namespace armature
