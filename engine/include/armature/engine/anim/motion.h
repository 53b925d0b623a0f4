// Motions: clips composed in layers (override blends, additive layers, joint
// masks, time sync, root motion), with three.js AnimationMixer's semantics so
// a browser that mixes locally shows the server's pose.
//
// A Motion is a description (clips by pointer, weights, modes); BindMotion
// validates it and resolves everything that does not depend on time (joint
// maps by name, mask weights, additive reference poses, root-motion frames)
// into a MotionPlan; BlendMotionJob samples and blends a plan at one time into
// a local pose without allocating (ozz's job style).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "armature/base/status.h"
#include "armature/engine/anim/clip.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/skeleton.h"
#include "armature/engine/math/transform.h"

namespace armature {

enum class LayerMode { kOverride, kAdditive };
enum class TimeSync { kNone, kPhase };
enum class RootMotion { kKeep, kInPlace, kAccumulate, kExtract };

// A mask entry: the joint and all its descendants, at `weight` (a more
// specific entry inside another one overrides it for its own subtree).
struct MaskJoint {
  std::string joint;
  double weight = 1;
};

struct MotionLayer {
  std::shared_ptr<const CompressedClip> clip;  // sampled through ClipSamplingJob
  std::string clip_name;                       // for messages
  double weight = 1;                           // 0..1
  double speed = 1;
  double time_offset = 0;  // seconds of clip time
  LayerMode mode = LayerMode::kOverride;
  double reference_time = 0;    // ADDITIVE: clip time of the reference pose
  std::vector<MaskJoint> mask;  // empty: the whole skeleton
  WrapMode wrap = WrapMode::kLoop;
};

struct Motion {
  std::vector<MotionLayer> layers;
  TimeSync sync = TimeSync::kNone;
  RootMotion root_motion = RootMotion::kKeep;
  std::string root_joint;  // the joint root motion acts on; empty: chosen (see BindMotion)
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();
};

// One layer resolved against the motion's skeleton (the first layer's).
struct BoundLayer {
  const CompressedClip* clip = nullptr;  // kept alive by MotionPlan::clips
  double weight = 1, speed = 1, time_offset = 0;
  LayerMode mode = LayerMode::kOverride;
  WrapMode wrap = WrapMode::kLoop;
  // Per motion joint: the clip's joint index, and the layer's weight there
  // (weight × mask weight; 0 = the layer leaves the joint alone).
  std::vector<int> clip_joint;
  std::vector<double> joint_weight;
  std::vector<Trs> reference;  // ADDITIVE: per motion joint, the clip at reference_time
  // The clip joints the blend reads (those of its joint_layers entries), when
  // not all: the job samples only these (a masked layer's few joints).
  std::optional<ClipJointSubset> sampled;
  // An override layer of a lossy clip that a float-lane joint reads (see
  // FloatBlendPlan): sampled into float lanes (ClipSamplingFloatJob) at
  // `sampled`'s joints, and as double transforms only at `doubles`' (the
  // joints the double path reads from it, when any).
  bool float_lanes = false;
  std::optional<ClipJointSubset> doubles;
  // Root motion (override layers). IN_PLACE: the root's translation in the
  // clip's first frame. ACCUMULATE: one loop moves the root, in world
  // directions, by x ↦ R(yaw)·(x − loop_origin) + loop_origin + loop_shift.
  Eigen::Vector3d root_first = Eigen::Vector3d::Zero();
  Eigen::Vector3d loop_origin = Eigen::Vector3d::Zero(), loop_shift = Eigen::Vector3d::Zero();
  double loop_yaw = 0;
};

// One layer acting on one joint: it has weight there and a track.
struct JointLayer {
  uint32_t layer = 0;
  bool additive = false;
  uint8_t parts = 0;   // what the clip animates there (CompressedClip::animated_parts)
  uint32_t joint = 0;  // the clip's joint
};

// The float-lane blend (issue 30). A joint other than the root-motion joint
// on which every layer acting is an override layer of a lossy clip blends
// from its layers' float lanes, four joints per vector (three.js's
// accumulation in float, slerpFlat by a series; no libm call), and its
// transform is written in double once, rotations made unit in double.
// Additive layers, exact clips and the root-motion joint keep the double
// path. A source: one layer's value of one joint property, `offset` floats
// into that layer's lanes.
struct FloatBlendSource {
  uint32_t layer = 0;
  uint32_t offset = 0;
};

// One property of four joints, each with `steps` layers acting: step k of
// lane i reads sources[first + 4k + i]. Lanes from `lanes` on repeat the
// last joint (blended, not written).
struct FloatBlendGroup {
  uint32_t joints[4] = {};
  uint32_t lanes = 0, steps = 0, first = 0;
};

struct FloatBlendPlan {
  std::vector<uint8_t> float_joint;  // per joint: 1 when it blends in float lanes
  // Per property, the groups of float joints a layer animates; a float
  // joint's other properties keep the rest pose. A property whose layers
  // all hold the rest value still (no track, rest or constant at rest) takes
  // the rest pose as well: the mixer would return it (slerpFlat of equal
  // quaternions is the first).
  std::vector<FloatBlendGroup> rotations, translations, scales;
  std::vector<FloatBlendSource> sources;
  // The skeleton's rest pose as lanes (4, 3, 3 floats a joint, padded by
  // one), the value a total weight below 1 is filled with.
  std::vector<float> rest;
};

struct MotionPlan {
  std::shared_ptr<const Skeleton> skeleton;  // the first layer's
  std::vector<std::shared_ptr<const CompressedClip>> clips;
  std::vector<BoundLayer> layers;
  // Per joint j, the layers acting on it in layer order:
  // joint_layers[joint_begin[j] .. joint_begin[j + 1]). A layer without weight
  // or without a track at a joint adds nothing there (three.js binds tracks),
  // so the blend visits only these; a joint with none keeps its rest transform.
  std::vector<uint32_t> joint_begin;
  std::vector<JointLayer> joint_layers;
  TimeSync sync = TimeSync::kNone;
  int phase_layer = -1;  // PHASE: the first override layer
  RootMotion root_motion = RootMotion::kKeep;
  int root = -1;  // the root-motion joint (-1 with KEEP)
  // Root-motion frame: the root's parent in world space (rest pose), its
  // inverse, the up axis in the parent's frame, and P = G⁻¹·(I − u·uᵀ)·G which
  // maps a parent-frame translation to its horizontal part.
  Eigen::Matrix3d parent_linear = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d parent_inverse = Eigen::Matrix3d::Identity();
  Eigen::Quaterniond parent_rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d up_world = Eigen::Vector3d::UnitY();
  Eigen::Matrix3d horizontal = Eigen::Matrix3d::Identity();
  FloatBlendPlan float_blend;
  // The joints with layers acting that are not float joints: BlendMotionJob
  // blends these in double.
  std::vector<uint32_t> double_joints;
};

// kFloatLanes blends what it can in float lanes (FloatBlendPlan); kDouble
// blends every joint in double (the reference the float lanes are tested
// against).
enum class BlendPath { kFloatLanes, kDouble };

// Validates `motion` and resolves it. Errors are INVALID_ARGUMENT (or
// NOT_FOUND for an unknown mask or root joint) naming the layer ("layer 1
// (clip 'Wave')") and the joint or field. Layers on another skeleton map by
// joint name (MapJointsByName): the clip's skeleton must have every joint of
// the motion's; joints only it has are ignored.
// The root-motion joint, unless named, is the joint with a translation track
// in the first override layer's clip that has the most descendants (the hips).
StatusOr<MotionPlan> BindMotion(const Motion& motion, BlendPath path = BlendPath::kFloatLanes);

// Where each layer plays at a motion time: the wrapped clip time and the
// number of completed loops (for ACCUMULATE).
struct LayerTime {
  double time = 0;
  long long loops = 0;
};

// Scratch space reused across evaluations (sized by Resize, never in Run):
// per layer its time, its clip's pose (as double transforms, and as float
// lanes for a float_lanes layer: 4, 3, 3 floats a joint and one of padding,
// as the blend loads four floats at a time; Resize writes the clip's still
// pose there once, the blend then only its animated tracks) and the
// sampling job's context.
struct MotionWorkspace {
  std::vector<LayerTime> layer_times;
  std::vector<std::vector<Trs>> layer_poses;
  std::vector<std::vector<float>> layer_lanes;
  std::vector<ClipSamplingContext> contexts;
  void Resize(const MotionPlan& plan);
};

// The root's motion that EXTRACT takes out of the pose: the accumulated
// root (as ACCUMULATE would place it) = translation + rotation · in-place root,
// in the root's parent frame.
struct RootDelta {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
};

// Samples and blends a plan at `time` into `output` (local transforms, one
// per skeleton joint). Per joint and per property (translation, rotation,
// scale), as three.js's PropertyMixer: the override layers that animate it
// accumulate in layer order, each slerped (lerped) toward by its weight over
// the weight so far; a total below 1 is filled with the rest pose; then the
// additive layers apply, q = q·slerp(1, q_ref⁻¹·q_clip, w),
// t = t + w·(t_clip − t_ref), s = s + w·(s_clip − s_ref).
struct BlendMotionJob {
  const MotionPlan* plan = nullptr;
  double time = 0;
  MotionWorkspace* workspace = nullptr;
  std::span<Trs> output;
  RootDelta* root_delta = nullptr;  // EXTRACT: receives the root's motion (optional)

  Status Validate() const;
  Status Run() const;  // Validate, then blend; no allocation
};

// Where layer `layer` of `plan` plays at motion time `time` (time sync applied).
LayerTime LayerTimeAt(const MotionPlan& plan, size_t layer, double time);

}  // namespace armature
