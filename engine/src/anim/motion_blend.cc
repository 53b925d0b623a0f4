// BlendMotionJob: samples a bound motion's layers and blends them per joint,
// the way three.js's AnimationMixer does (PropertyMixer.accumulate / apply).
#include <algorithm>
#include <cmath>
#include <string>

#include "anim/motion_float_blend.h"
#include "armature/engine/anim/motion.h"
#include "armature/engine/math/rotation.h"

namespace armature {
namespace {

// Completed loops are counted as a double first: a huge time must not
// overflow the integer.
constexpr double kMaxLoops = 1e15;

LayerTime Wrapped(double raw, double duration, WrapMode wrap) {
  if (!(duration > 0)) return {};
  if (wrap == WrapMode::kClamp) return {std::clamp(raw, 0.0, duration), 0};
  const double loops = std::clamp(std::floor(raw / duration), -kMaxLoops, kMaxLoops);
  double t = raw - loops * duration;
  long long n = static_cast<long long>(loops);
  if (t >= duration) t -= duration, ++n;  // rounding at the loop point
  if (t < 0) t = 0;
  return {t, n};
}

// PropertyMixer's mix functions: lerp for vectors, slerpFlat for rotations.
Eigen::Vector3d Mix(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t) { return a * (1 - t) + b * t; }
Eigen::Quaterniond Mix(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b, double t) {
  return SlerpFlat(a, b, t);
}

// One property's weighted accumulation (PropertyMixer.accumulate / apply).
template <class V>
struct Accumulator {
  V value;
  double weight = 0;
  void Add(const V& v, double w) {
    if (weight == 0) {
      value = v;
      weight = w;
      return;
    }
    weight += w;
    value = Mix(value, v, w / weight);
  }
  // A total weight below 1 is filled with the rest value.
  V Finish(const V& rest) const {
    if (weight == 0) return rest;
    return weight < 1 ? Mix(value, rest, 1 - weight) : value;
  }
};

// A Euclidean motion of the horizontal plane, x ↦ r·x + c (world directions).
struct Rigid {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  Rigid Then(const Rigid& next) const { return {next.r * r, next.r * c + next.c}; }
  Rigid Inverse() const { return {r.transpose(), -(r.transpose() * c)}; }
};

// `n` loops of layer `l`: the loop's motion composed n times, O(log n).
Rigid LoopMotion(const MotionPlan& plan, const BoundLayer& l, long long n) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(l.loop_yaw, plan.up_world).toRotationMatrix();
  Rigid one{r, l.loop_origin + l.loop_shift - r * l.loop_origin};
  if (n < 0) one = one.Inverse(), n = -n;
  Rigid result;
  for (Rigid power = one; n > 0; n >>= 1, power = power.Then(power))
    if (n & 1) result = result.Then(power);
  return result;
}

// The root joint's sample of an override layer, with root motion applied.
void ApplyRootMotion(const MotionPlan& plan, const BoundLayer& l, const LayerTime& lt, RootMotion mode, Trs& v) {
  if (mode == RootMotion::kInPlace) {
    v.translation -= plan.horizontal * (v.translation - l.root_first);
  } else if (mode == RootMotion::kAccumulate && lt.loops != 0) {
    const Rigid m = LoopMotion(plan, l, lt.loops);
    v.translation = plan.parent_inverse * (m.r * (plan.parent_linear * v.translation) + m.c);
    const Eigen::Quaterniond yaw(Eigen::AngleAxisd(static_cast<double>(lt.loops) * l.loop_yaw, plan.up_world));
    v.rotation = plan.parent_rotation.conjugate() * yaw * plan.parent_rotation * v.rotation;
  }
}

// Layer `e`'s sample of its joint: the rest transform, with what the clip animates there replaced.
Trs LayerSample(const MotionWorkspace& ws, const JointLayer& e, const Trs& rest) {
  const Trs& sampled = ws.layer_poses[e.layer][e.joint];
  Trs v = rest;
  if (e.parts & 1) v.rotation = sampled.rotation;
  if (e.parts & 2) v.translation = sampled.translation;
  if (e.parts & 4) v.scale = sampled.scale;
  return v;
}

// One joint of the blended pose, from the layers acting on it (plan.joint_layers), their clips'
// poses sampled in `ws`.
void BlendJoint(const MotionPlan& plan, const MotionWorkspace& ws, size_t j, RootMotion root_mode, Trs& out) {
  std::span<const LayerTime> times(ws.layer_times);
  const Trs& rest = plan.skeleton->rest[j];
  const JointLayer* begin = plan.joint_layers.data() + plan.joint_begin[j];
  const JointLayer* end = plan.joint_layers.data() + plan.joint_begin[j + 1];
  if (begin == end) {
    out = rest;
    return;
  }
  const bool is_root = static_cast<int>(j) == plan.root;
  // One override layer at full weight: the mixer takes its sample as it is.
  if (end - begin == 1 && !begin->additive && plan.layers[begin->layer].joint_weight[j] >= 1 && !is_root) {
    out = LayerSample(ws, *begin, rest);
    return;
  }
  Accumulator<Eigen::Vector3d> t{Eigen::Vector3d::Zero()}, s{Eigen::Vector3d::Zero()};
  Accumulator<Eigen::Quaterniond> r{Eigen::Quaterniond::Identity()};
  bool additive = false;
  for (const JointLayer* e = begin; e != end; ++e) {
    if (e->additive) {
      additive = true;
      continue;
    }
    const double w = plan.layers[e->layer].joint_weight[j];
    // Only the properties the clip animates take part (three.js binds tracks,
    // not joints), read in place: the root alone needs a copy to move.
    Trs moved;
    const Trs* v = &ws.layer_poses[e->layer][e->joint];
    if (is_root) {
      moved = LayerSample(ws, *e, rest);
      ApplyRootMotion(plan, plan.layers[e->layer], times[e->layer], root_mode, moved);
      v = &moved;
    }
    if (e->parts & 2) t.Add(v->translation, w);
    if (e->parts & 1) r.Add(v->rotation, w);
    if (e->parts & 4) s.Add(v->scale, w);
  }
  out.translation = t.Finish(rest.translation);
  out.rotation = r.Finish(rest.rotation);
  out.scale = s.Finish(rest.scale);
  if (!additive) return;
  // Additive layers (PropertyMixer.accumulateAdditive): from identity, each
  // layer slerps toward add·delta by its weight; apply: q·add, t + add, s + add.
  Eigen::Vector3d add_t = Eigen::Vector3d::Zero(), add_s = Eigen::Vector3d::Zero();
  Eigen::Quaterniond add_r = Eigen::Quaterniond::Identity();
  for (const JointLayer* e = begin; e != end; ++e) {
    if (!e->additive) continue;
    const Trs& ref = plan.layers[e->layer].reference[j];
    const double w = plan.layers[e->layer].joint_weight[j];
    const Trs v = LayerSample(ws, *e, rest);
    if (e->parts & 2) {
      Eigen::Vector3d d = v.translation - ref.translation;
      if (is_root && root_mode == RootMotion::kInPlace) d -= plan.horizontal * d;
      add_t += w * d;
    }
    if (e->parts & 1) add_r = SlerpFlat(add_r, add_r * (ref.rotation.conjugate() * v.rotation), w);
    if (e->parts & 4) add_s += w * (v.scale - ref.scale);
  }
  out.translation += add_t;
  out.rotation = out.rotation * add_r;
  out.scale += add_s;
}

}  // namespace

void MotionWorkspace::Resize(const MotionPlan& plan) {
  layer_times.resize(plan.layers.size());
  layer_poses.resize(plan.layers.size());
  layer_lanes.resize(plan.layers.size());
  contexts.resize(plan.layers.size());
  for (size_t i = 0; i < plan.layers.size(); ++i) {
    const CompressedClip& clip = *plan.layers[i].clip;
    const size_t joints = clip.skeleton->size();
    layer_poses[i].resize(joints);
    const size_t lanes = plan.layers[i].float_lanes ? 10 * joints + 1 : 0;  // padded: four floats load from the last
    bool stale = layer_lanes[i].size() != lanes;
    layer_lanes[i].resize(lanes);
    if (!contexts[i].Fits(clip)) contexts[i].Resize(clip), stale = true;
    if (lanes == 0 || !stale) continue;
    // The clip's still pose (rest and constant tracks) written once: the
    // blend's jobs then write only the animated tracks (still_written). The
    // clip was checked when bound.
    const std::span<float> l(layer_lanes[i]);
    const FloatPose pose{l.subspan(0, 4 * joints), l.subspan(4 * joints, 3 * joints),
                         l.subspan(7 * joints, 3 * joints)};
    (void)ClipSamplingFloatJob{&clip, 0.0, WrapMode::kClamp, &contexts[i], pose}.Run();
  }
}

LayerTime LayerTimeAt(const MotionPlan& plan, size_t layer, double time) {
  const BoundLayer& l = plan.layers[layer];
  if (plan.sync == TimeSync::kPhase) {
    const BoundLayer& driver = plan.layers[plan.phase_layer];
    const double d = driver.clip->duration;
    if (!(d > 0)) return {};
    // The driver's normalized time; every layer plays at that fraction of its length.
    const LayerTime phase = Wrapped((time * driver.speed + driver.time_offset) / d, 1.0, driver.wrap);
    return {phase.time * l.clip->duration, l.wrap == WrapMode::kLoop ? phase.loops : 0};
  }
  return Wrapped(time * l.speed + l.time_offset, l.clip->duration, l.wrap);
}

Status BlendMotionJob::Validate() const {
  if (!plan || !plan->skeleton) return Status::InvalidArgument("blend job: no motion plan");
  if (!workspace || workspace->layer_times.size() != plan->layers.size() ||
      workspace->contexts.size() != plan->layers.size())
    return Status::InvalidArgument("blend job: the workspace is not sized for this motion (call Resize)");
  if (workspace->layer_lanes.size() != plan->layers.size())
    return Status::InvalidArgument("blend job: the workspace is not sized for this motion (call Resize)");
  for (size_t i = 0; i < plan->layers.size(); ++i) {
    const BoundLayer& l = plan->layers[i];
    if (!workspace->contexts[i].Fits(*l.clip) ||
        workspace->layer_lanes[i].size() != (l.float_lanes ? 10 * l.clip->skeleton->size() + 1 : 0))
      return Status::InvalidArgument("blend job: the workspace is not sized for this motion (call Resize)");
  }
  if (plan->joint_begin.size() != plan->skeleton->size() + 1)
    return Status::InvalidArgument("blend job: the motion plan is not bound (use BindMotion)");
  if (output.size() != plan->skeleton->size())
    return Status::InvalidArgument("blend job: output has room for " + std::to_string(output.size()) +
                                   " transforms, the skeleton has " + std::to_string(plan->skeleton->size()) +
                                   " joints");
  if (!std::isfinite(time)) return Status::InvalidArgument("time is not finite");
  return Status::Ok();
}

namespace {

// Layer `i`'s clip at `time` (already wrapped), only at the joints the blend
// reads: as float lanes and double transforms for a float_lanes layer, as
// double transforms for the others.
Status SampleLayer(const BoundLayer& l, double time, MotionWorkspace& ws, size_t i) {
  const ClipJointSubset* sampled = l.sampled ? &*l.sampled : nullptr;
  if (!l.float_lanes)
    return ClipSamplingJob{l.clip, time, WrapMode::kClamp, &ws.contexts[i], ws.layer_poses[i], {}, sampled}.Run();
  const size_t n = l.clip->skeleton->size();
  const std::span<float> lanes(ws.layer_lanes[i]);
  const FloatPose pose{lanes.subspan(0, 4 * n), lanes.subspan(4 * n, 3 * n), lanes.subspan(7 * n, 3 * n)};
  ARMATURE_RETURN_IF_ERROR(
      (ClipSamplingFloatJob{l.clip, time, WrapMode::kClamp, &ws.contexts[i], pose, sampled, true}.Run()));
  if (!l.doubles) return Status::Ok();
  return ClipSamplingJob{l.clip, time, WrapMode::kClamp, &ws.contexts[i], ws.layer_poses[i], {}, &*l.doubles}.Run();
}

}  // namespace

Status BlendMotionJob::Run() const {
  ARMATURE_RETURN_IF_ERROR(Validate());
  const MotionPlan& p = *plan;
  std::span<LayerTime> times(workspace->layer_times);
  for (size_t i = 0; i < p.layers.size(); ++i) {
    times[i] = LayerTimeAt(p, i, time);
    ARMATURE_RETURN_IF_ERROR(SampleLayer(p.layers[i], times[i].time, *workspace, i));
  }
  const bool extract = p.root_motion == RootMotion::kExtract;
  const RootMotion mode = extract ? RootMotion::kInPlace : p.root_motion;
  // The rest pose first, in one copy: joints without layers keep it, and
  // float joints the properties no group writes. A copy of the whole pose
  // (8 KB for RobotExpressive's 84 joints) took about half the time of
  // copying its 60 still joints and 24 still properties one by one. Trs is
  // plain doubles (Eigen's fixed sizes), so its bytes are its value.
  __builtin_memcpy(static_cast<void*>(output.data()), p.skeleton->rest.data(), output.size() * sizeof(Trs));
  for (uint32_t j : p.double_joints) BlendJoint(p, *workspace, j, mode, output[j]);
  motion_internal::BlendFloatJoints(p, *workspace, output);
  if (extract && root_delta) {
    Trs accumulated;
    BlendJoint(p, *workspace, static_cast<size_t>(p.root), RootMotion::kAccumulate, accumulated);
    const Trs& in_place = output[p.root];
    root_delta->translation = accumulated.translation - in_place.translation;
    root_delta->rotation = (accumulated.rotation * in_place.rotation.conjugate()).normalized();
  }
  return Status::Ok();
}

}  // namespace armature
