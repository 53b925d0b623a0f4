// BindMotion: a motion's validation and everything resolved once per motion.
#include <algorithm>
#include <cmath>
#include <string>

#include "anim/motion_float_blend.h"
#include "armature/engine/anim/joint_map.h"
#include "armature/engine/anim/motion.h"

namespace armature {
namespace {

std::string LayerName(const MotionLayer& layer, size_t i) {
  return "layers[" + std::to_string(i) + "] (clip '" + layer.clip_name + "')";
}

Status CheckLayerNumbers(const MotionLayer& l, const std::string& where) {
  if (!std::isfinite(l.weight) || l.weight < 0 || l.weight > 1)
    return Status::InvalidArgument(where + ": weight " + std::to_string(l.weight) + " is outside [0, 1]");
  if (!std::isfinite(l.speed)) return Status::InvalidArgument(where + ": speed is not finite");
  if (!std::isfinite(l.time_offset)) return Status::InvalidArgument(where + ": timeOffset is not finite");
  if (!std::isfinite(l.reference_time) || l.reference_time < 0)
    return Status::InvalidArgument(where + ": referenceTime " + std::to_string(l.reference_time) +
                                   " is not a finite time >= 0");
  if (l.mode != LayerMode::kOverride && l.mode != LayerMode::kAdditive)
    return Status::InvalidArgument(where + ": mode " + std::to_string(static_cast<int>(l.mode)) +
                                   " is not OVERRIDE or ADDITIVE");
  if (l.wrap != WrapMode::kLoop && l.wrap != WrapMode::kClamp)
    return Status::InvalidArgument(where + ": wrap " + std::to_string(static_cast<int>(l.wrap)) +
                                   " is not LOOP or CLAMP");
  for (const MaskJoint& m : l.mask)
    if (!std::isfinite(m.weight) || m.weight < 0 || m.weight > 1)
      return Status::InvalidArgument(where + ": mask weight " + std::to_string(m.weight) + " of joint '" + m.joint +
                                     "' is outside [0, 1]");
  return Status::Ok();
}

// Per joint: the weight of the nearest mask entry at or above it; 1 everywhere without a mask.
Status MaskWeights(const Skeleton& sk, const std::vector<MaskJoint>& mask, const std::string& where,
                   std::vector<double>& out) {
  out.assign(sk.size(), mask.empty() ? 1.0 : 0.0);
  if (mask.empty()) return Status::Ok();
  std::vector<double> entry(sk.size(), -1.0);
  for (const MaskJoint& m : mask) {
    const int j = sk.Find(m.joint);
    if (j < 0) return Status::NotFound(where + ": mask joint '" + m.joint + "' is not in the skeleton");
    entry[j] = m.weight;
  }
  for (size_t j = 0; j < sk.size(); ++j) {  // parents come before children
    if (entry[j] >= 0)
      out[j] = entry[j];
    else if (sk.parents[j] >= 0)
      out[j] = out[sk.parents[j]];
  }
  return Status::Ok();
}

// The clip's pose at `time` (clamped), through the sampling job.
std::vector<Trs> SampleClipPose(const CompressedClip& clip, double time) {
  std::vector<Trs> pose(clip.skeleton->size());
  (void)ClipSamplingJob{&clip, time, WrapMode::kClamp, nullptr, pose, {}}.Run();  // the clip was checked when bound
  return pose;
}

// The joint with a translation track in `layer`'s clip that has the most descendants.
int ChooseRoot(const Skeleton& sk, const BoundLayer& layer) {
  std::vector<int> descendants(sk.size(), 0);
  for (size_t j = sk.size(); j-- > 0;)
    if (sk.parents[j] >= 0) descendants[sk.parents[j]] += descendants[j] + 1;
  int best = -1;
  for (size_t j = 0; j < sk.size(); ++j)
    if ((layer.clip->animated_parts[layer.clip_joint[j]] & 2) != 0 && (best < 0 || descendants[j] > descendants[best]))
      best = static_cast<int>(j);
  return best < 0 ? 0 : best;
}

// The root's parent frame (rest pose) and, per override layer, the
// first-frame root and the motion of one loop.
Status BindRoot(const Motion& motion, MotionPlan& plan) {
  const Skeleton& sk = *plan.skeleton;
  if (!motion.up.allFinite() || motion.up.norm() < 1e-12)
    return Status::InvalidArgument("up: not a finite non-zero vector");
  if (plan.phase_layer < 0) return Status::InvalidArgument("rootMotion: needs an OVERRIDE layer");
  if (!motion.root_joint.empty()) {
    plan.root = sk.Find(motion.root_joint);
    if (plan.root < 0) return Status::NotFound("rootJoint: '" + motion.root_joint + "' is not in the skeleton");
  } else {
    plan.root = ChooseRoot(sk, plan.layers[plan.phase_layer]);
  }
  Eigen::Affine3d parent = Eigen::Affine3d::Identity();
  Eigen::Quaterniond parent_rotation = Eigen::Quaterniond::Identity();
  for (int p = sk.parents[plan.root]; p >= 0; p = sk.parents[p]) {
    parent = sk.rest[p].ToAffine() * parent;
    parent_rotation = sk.rest[p].rotation.normalized() * parent_rotation;
  }
  plan.parent_linear = parent.linear();
  if (std::abs(plan.parent_linear.determinant()) < 1e-300)
    return Status::InvalidArgument("rootJoint: its parents have a degenerate rest transform");
  plan.parent_inverse = plan.parent_linear.inverse();
  plan.parent_rotation = parent_rotation;
  plan.up_world = motion.up.normalized();
  const Eigen::Matrix3d h = Eigen::Matrix3d::Identity() - plan.up_world * plan.up_world.transpose();
  plan.horizontal = plan.parent_inverse * h * plan.parent_linear;
  for (BoundLayer& l : plan.layers) {
    const int cj = l.clip_joint[plan.root];
    const Trs first = SampleClipPose(*l.clip, 0)[cj], last = SampleClipPose(*l.clip, l.clip->duration)[cj];
    l.root_first = first.translation;
    l.loop_origin = plan.parent_linear * first.translation;
    l.loop_shift = h * plan.parent_linear * (last.translation - first.translation);
    // Yaw of one loop: the twist about up of the root's world rotation change.
    const Eigen::Quaterniond change =
        parent_rotation * last.rotation * first.rotation.conjugate() * parent_rotation.conjugate();
    l.loop_yaw = 2.0 * std::atan2(change.vec().dot(plan.up_world), change.w());
  }
  return Status::Ok();
}

// Per joint, the layers with weight and a track there, in layer order. The weight itself is read
// from layers[i].joint_weight when blending, so a caller (Playback) may rescale it without binding again.
void IndexJointLayers(MotionPlan& plan) {
  const size_t n = plan.skeleton->size();
  plan.joint_begin.assign(n + 1, 0);
  plan.joint_layers.clear();
  for (size_t j = 0; j < n; ++j) {
    plan.joint_begin[j] = static_cast<uint32_t>(plan.joint_layers.size());
    for (size_t i = 0; i < plan.layers.size(); ++i) {
      const BoundLayer& l = plan.layers[i];
      const uint8_t parts = l.clip->animated_parts[l.clip_joint[j]];
      if (!(l.joint_weight[j] > 0) || parts == 0) continue;
      plan.joint_layers.push_back(
          {static_cast<uint32_t>(i), l.mode == LayerMode::kAdditive, parts, static_cast<uint32_t>(l.clip_joint[j])});
    }
  }
  plan.joint_begin[n] = static_cast<uint32_t>(plan.joint_layers.size());
}

std::vector<uint32_t> SortedUnique(std::vector<uint32_t> v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

// Each layer's clip joints the blend reads: in float lanes (float joints)
// or as double transforms (the other joints), so its jobs sample only those;
// and the joints blended in double.
void ChooseSampledJoints(MotionPlan& plan) {
  const std::vector<uint8_t>& float_joint = plan.float_blend.float_joint;
  std::vector<std::vector<uint32_t>> lanes(plan.layers.size()), doubles(plan.layers.size());
  for (size_t j = 0; j + 1 < plan.joint_begin.size(); ++j)
    for (uint32_t e = plan.joint_begin[j]; e < plan.joint_begin[j + 1]; ++e) {
      const JointLayer& entry = plan.joint_layers[e];
      (!float_joint.empty() && float_joint[j] ? lanes : doubles)[entry.layer].push_back(entry.joint);
    }
  for (size_t i = 0; i < plan.layers.size(); ++i) {
    BoundLayer& l = plan.layers[i];
    const std::vector<uint32_t> read = SortedUnique(l.float_lanes ? lanes[i] : doubles[i]);
    if (read.size() < l.clip->skeleton->size()) l.sampled.emplace(*l.clip, read);
    if (l.float_lanes && !doubles[i].empty()) l.doubles.emplace(*l.clip, SortedUnique(doubles[i]));
  }
  plan.double_joints.clear();
  for (uint32_t j = 0; j + 1 < plan.joint_begin.size(); ++j)
    if (plan.joint_begin[j] != plan.joint_begin[j + 1] && (float_joint.empty() || !float_joint[j]))
      plan.double_joints.push_back(j);
}

}  // namespace

StatusOr<MotionPlan> BindMotion(const Motion& motion, BlendPath path) {
  if (motion.layers.empty()) return Status::InvalidArgument("layers: the motion is empty (give at least one layer)");
  if (motion.sync != TimeSync::kNone && motion.sync != TimeSync::kPhase)
    return Status::InvalidArgument("sync: " + std::to_string(static_cast<int>(motion.sync)) + " is not NONE or PHASE");
  const RootMotion rm = motion.root_motion;
  if (rm != RootMotion::kKeep && rm != RootMotion::kInPlace && rm != RootMotion::kAccumulate &&
      rm != RootMotion::kExtract)
    return Status::InvalidArgument("rootMotion: " + std::to_string(static_cast<int>(rm)) +
                                   " is not KEEP, IN_PLACE, ACCUMULATE or EXTRACT");
  MotionPlan plan;
  plan.sync = motion.sync;
  plan.root_motion = rm;
  for (size_t i = 0; i < motion.layers.size(); ++i) {
    const MotionLayer& l = motion.layers[i];
    const std::string where = LayerName(l, i);
    if (!l.clip || !l.clip->skeleton) return Status::InvalidArgument(where + ": no clip");
    ARMATURE_RETURN_IF_ERROR(CheckLayerNumbers(l, where));
    if (l.clip->animated_parts.size() != l.clip->skeleton->size())
      return Status::InvalidArgument(where + ": the clip's tracks do not match its skeleton");
    if (i == 0) plan.skeleton = l.clip->skeleton;
    const Skeleton& sk = *plan.skeleton;
    BoundLayer b;
    b.clip = l.clip.get();
    b.weight = l.weight;
    b.speed = l.speed;
    b.time_offset = l.time_offset;
    b.mode = l.mode;
    b.wrap = l.wrap;
    // By name when the layer's clip animates another skeleton (joint_map.h).
    if (Status mapped = MapJointsByName(sk, *l.clip->skeleton, "the motion's skeleton (layers[0]'s)", b.clip_joint);
        !mapped.ok())
      return Status::InvalidArgument(where + ": the clip's skeleton " + mapped.message());
    ARMATURE_RETURN_IF_ERROR(MaskWeights(sk, l.mask, where, b.joint_weight));
    for (double& w : b.joint_weight) w *= l.weight;
    if (l.mode == LayerMode::kAdditive) {
      b.reference.resize(sk.size());
      const std::vector<Trs> reference = SampleClipPose(*l.clip, l.reference_time);
      for (size_t j = 0; j < sk.size(); ++j) b.reference[j] = reference[b.clip_joint[j]];
    }
    if (l.mode == LayerMode::kOverride && plan.phase_layer < 0) plan.phase_layer = static_cast<int>(i);
    plan.clips.push_back(l.clip);
    plan.layers.push_back(std::move(b));
  }
  if (plan.sync == TimeSync::kPhase && plan.phase_layer < 0)
    return Status::InvalidArgument("sync: PHASE needs an OVERRIDE layer to drive the phase");
  if (rm != RootMotion::kKeep) ARMATURE_RETURN_IF_ERROR(BindRoot(motion, plan));
  IndexJointLayers(plan);
  if (path == BlendPath::kFloatLanes) motion_internal::BindFloatBlend(plan);
  ChooseSampledJoints(plan);
  return plan;
}

}  // namespace armature
