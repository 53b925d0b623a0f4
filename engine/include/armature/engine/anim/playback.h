// Live playback of motions (PoseService.PlaybackSession): the motion playing
// now, the motions fading out, pause, resume, seek, and per-layer weight and
// speed. Pure: it has no clock; its owner calls Advance(dt) once per frame.
//
// Crossfades are three.js's crossFadeTo without warping: Play(m, d) ramps
// every motion playing now linearly from its weight to 0 over d seconds and
// `m` from 0 to 1; `m` starts at its time 0, the others keep running. The
// blend is every playing motion's layers in play order, each layer's weight
// times its motion's weight, mixed as BlendMotionJob mixes one motion's
// layers (three.js's mixer accumulating its actions).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "armature/base/status.h"
#include "armature/engine/anim/motion.h"

namespace armature {

// One playing motion as a frame reports it.
struct PlayingMotion {
  uint64_t id = 0;    // the id given to Play
  double weight = 0;  // its fade weight now (0..1)
  double time = 0;    // its own motion time now
};

class Playback {
 public:
  // At most this many motions play at once; one more drops the oldest.
  static constexpr size_t kMaxMotions = 8;

  // Every motion played must be on `skeleton` (the same joint names in the same order).
  explicit Playback(std::shared_ptr<const Skeleton> skeleton);

  // Plays `motion` from its time 0, fading the playing motions out over
  // `crossfade` seconds (0: a cut). Errors (BindMotion's, a bad crossfade, a
  // skeleton mismatch) are INVALID_ARGUMENT and leave the playback as it was.
  Status Play(const Motion& motion, double crossfade, uint64_t id);
  // The newest motion's layer `layer`: its weight (0..1), or its speed, kept
  // continuous (the layer's time does not jump where the speed changes).
  Status SetLayerWeight(size_t layer, double weight);
  Status SetLayerSpeed(size_t layer, double speed);
  // Pausing stops every motion's time and every fade; frames keep showing the pose.
  void Pause() { paused_ = true; }
  void Resume() { paused_ = false; }
  bool paused() const { return paused_; }
  // The newest motion jumps to `time` (finite, >= 0); fading motions keep theirs.
  Status Seek(double time);

  // Moves every motion's time and fade on by `dt` seconds (none while
  // paused); a motion whose fade-out is complete stops. No allocation.
  void Advance(double dt);

  // The pose now (local transforms, one per skeleton joint); the rest pose
  // when nothing plays. `workspace` is resized here when the blend's layer
  // count changed; `root_delta` as BlendMotionJob's (EXTRACT).
  Status Evaluate(MotionWorkspace& workspace, std::span<Trs> output, RootDelta* root_delta = nullptr) const;

  // The blend now as a description: evaluated at time 0 it is the pose
  // (sync NONE, each layer's weight its effective weight, its timeOffset its
  // clip time, speed 1). Empty layers when nothing plays. Allocates: for tests and tools.
  Motion Describe() const;

  size_t playing_count() const { return motions_.size(); }
  // The layers each frame blends: those of every playing motion.
  size_t layer_count() const { return blend_.layers.size(); }
  PlayingMotion playing(size_t i) const;  // 0 = the oldest; playing_count() - 1 = the newest
  const Skeleton& skeleton() const { return *skeleton_; }
  // The blend's root-motion mode (the newest motion's).
  RootMotion root_motion() const { return blend_.root_motion; }

 private:
  struct Entry {
    uint64_t id = 0;
    Motion motion;    // as played, with SetLayer* applied
    MotionPlan plan;  // bound: its layers' times (PHASE) and speeds
    double time = 0;  // motion time
    double weight_from = 0, weight_to = 1, fade_elapsed = 0, fade_duration = 0;
    double Weight() const;
    bool FadedOut() const;
  };
  Status CheckLayer(size_t layer) const;
  Status Rebind();  // rebuilds blend_ after the playing motions changed
  void Refresh();   // writes the weights and times of now into blend_

  std::shared_ptr<const Skeleton> skeleton_;
  std::vector<Entry> motions_;  // oldest first
  bool paused_ = false;
  // Every playing layer bound once with weight 1 (joint_weight = its mask);
  // Refresh scales the weights and sets the times (as offsets at time 0).
  MotionPlan blend_;
  std::vector<std::vector<double>> mask_weights_;  // per blend layer, per joint
  std::vector<std::pair<size_t, size_t>> source_;  // per blend layer: motion, layer
};

}  // namespace armature
