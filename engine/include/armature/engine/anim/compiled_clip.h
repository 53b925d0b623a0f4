// A clip's runtime form: the keys of its uniformly sampled tracks (BVH,
// resampled glTF) as float structure-of-arrays, four joints per vector, found
// by direct indexing (no key search) and interpolated without trigonometry.
// The Clip it is built from stays the file form (export, motions, joint maps)
// and samples what the runtime form does not hold.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include "armature/base/status.h"
#include "armature/engine/anim/clip.h"
#include "armature/engine/math/transform.h"

namespace armature {

// Keys of one property (rotation, translation or scale) of the tracks in the
// uniform group, four tracks per lane group: `keys` holds, per frame and per
// group, `components` (4: x y z w, or 3: x y z) vectors of four floats.
struct CompiledLanes {
  size_t components = 0;
  size_t groups = 0;             // ceil(tracks / 4)
  std::vector<uint32_t> joints;  // joint per lane, tracks only (no padding)
  std::vector<float> linear;     // per lane (padded): 1 interpolates, 0 holds the key (STEP)
  std::vector<float> keys;       // frames × groups × components × 4; padding lanes are identity
};

struct CompiledClip {
  std::shared_ptr<const Clip> source;
  // The uniform group's key times, shared by all its tracks: key k is near
  // start + k·frame_time, so floor() finds it and at most one step corrects it.
  std::vector<double> times;
  double start = 0, frame_time = 0;
  CompiledLanes rotations, translations, scales;

  // Joints with a track outside the uniform group (uneven or single-key
  // times, glTF tangents, CUBIC): sampled from `source` with SampleJoint.
  std::vector<uint32_t> fallback_joints;

  // Squad's control point per rotation key, laid out as `rotations.keys`,
  // for CUBIC; empty when uneven times give a key two (CUBIC then samples
  // `source`). Computed on first use (thread-safe), so clips only sampled
  // LINEAR or STEP never hold them.
  const std::vector<float>& RotationControls() const;

  // Bytes of the runtime keys and times (not `source`), control points
  // included once computed.
  size_t KeyBytes() const;

 private:
  mutable std::once_flag controls_once_;
  mutable std::vector<float> rotation_controls_;
  mutable std::atomic<bool> controls_ready_{false};  // KeyBytes reads the size only once written
};

// Builds the runtime form of a valid clip (Clip::Validate passes).
StatusOr<std::shared_ptr<const CompiledClip>> CompileClip(std::shared_ptr<const Clip> clip);

// SampleClip on the runtime form: the same arguments, checks and poses (float
// keys: within 1e-6 of SampleClip's, relative for translations and scales,
// in radians for rotations). LINEAR rotations use a trig-free slerp (see
// src/anim/fast_slerp.h), CUBIC ones squad through the precomputed control
// points with the same slerp; vectors use CUBIC's Hermite weights. No allocation.
Status SampleCompiledClip(const CompiledClip& clip, double time, const SampleOptions& options, std::span<Trs> out);

}  // namespace armature
