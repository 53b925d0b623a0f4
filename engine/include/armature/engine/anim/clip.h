// Clips: per-joint keyframe tracks and the job that samples them at a time.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <span>
#include <vector>

#include <Eigen/Geometry>

#include "armature/engine/anim/skeleton.h"
#include "armature/base/status.h"
#include "armature/engine/math/transform.h"

namespace armature {

enum class Interpolation { kStep, kLinear, kCubic };
enum class WrapMode { kClamp, kLoop };

// Keys of one animated property. Times strictly increase. `in_tangents` and
// `out_tangents` are only set for glTF CUBICSPLINE samplers (already scaled
// to units per second); CUBIC sampling of a track without them uses
// Catmull-Rom (vectors) or squad (rotations).
template <class V>
struct Track {
  std::vector<double> times;
  std::vector<V> values;
  std::vector<V> in_tangents, out_tangents;
  Interpolation interpolation = Interpolation::kLinear;  // the track's own (file) interpolation

  bool empty() const { return times.empty(); }
};

using Vec3Track = Track<Eigen::Vector3d>;
using QuatTrack = Track<Eigen::Quaterniond>;

// One joint's tracks. An empty track leaves that part at the skeleton's rest value.
struct JointTrack {
  Vec3Track translation;
  QuatTrack rotation;
  Vec3Track scale;
};

// Animated morph-target weights of one mesh (glTF "weights" channel):
// `values` holds `targets` weights per key.
struct WeightsTrack {
  std::string mesh;  // the mesh asset's local name inside its file
  size_t targets = 0;
  std::vector<double> times;
  std::vector<double> values;  // times.size() × targets (× 3 for CUBICSPLINE: in, value, out)
  Interpolation interpolation = Interpolation::kLinear;
};

struct Clip {
  std::shared_ptr<const Skeleton> skeleton;
  std::vector<JointTrack> joints;  // one per skeleton joint
  std::vector<WeightsTrack> weights;
  double duration = 0;     // seconds; the last key time
  double frame_time = 0;   // seconds between frames when sampled uniformly (BVH), else 0
  size_t frame_count = 0;  // frames in the source (BVH frames, or the most keys of any track)
  Interpolation default_interpolation = Interpolation::kLinear;

  // Checks tracks against the skeleton: sizes, increasing times, finite, unit quaternions.
  Status Validate() const;
};

struct SampleOptions {
  // Empty: each track's own interpolation. Otherwise it overrides all tracks.
  std::optional<Interpolation> interpolation;
  WrapMode wrap = WrapMode::kClamp;
};

// Maps a request time onto the clip's [0, duration] by the wrap mode.
double WrapTime(double time, double duration, WrapMode wrap);

// Samples every joint's local transform at `time` into `out` (size = joints).
// No allocation. Rotations are slerped / squad-interpolated, never lerped.
Status SampleClip(const Clip& clip, double time, const SampleOptions& options, std::span<Trs> out);

// Samples one joint's tracks at clip time `t` (already wrapped) into `out`,
// which holds the joint's rest transform: empty tracks leave it as it is.
// No allocation; SampleClip's per-joint step, for callers that sample a few joints.
void SampleJoint(const JointTrack& track, double t, const std::optional<Interpolation>& interpolation, Trs& out);

// Samples the morph weights of `track` at `time` into `out` (size = targets).
void SampleWeights(const WeightsTrack& track, double time, const SampleOptions& options, std::span<double> out);

}  // namespace armature
