// The project's own demo asset: a walk cycle keyframed here (no third-party
// data), so a fresh install has something to play.
#pragma once

#include "armature/engine/io/bvh/bvh.h"

namespace armature {

// What MakeDemoWalk produces.
inline constexpr double kDemoWalkCycleSeconds = 1.0;  // one stride: left step + right step
inline constexpr int kDemoWalkCycles = 3;
inline constexpr double kDemoWalkFrameTime = 1.0 / 30.0;
inline constexpr double kDemoWalkSpeed = 110.0;     // cm/s along +Z
inline constexpr double kDemoWalkHipHeight = 93.0;  // cm, mean root height

// A 19-joint humanoid (Hips root with 6 channels; per side Hip, Knee, Ankle,
// Toe; Spine, Chest, Neck, Head; per side Shoulder, Elbow, Wrist; End Sites
// on toes, Head and wrists; joints in depth-first order as in a BVH file),
// in centimetres, Y up, facing +Z, left = +X.
// Joint rotations are keyframed at gait phases (hip flexion, knee, ankle,
// toe, arm swing, elbow, pelvis and chest yaw), the root bobs, and
// everything is sampled with the engine's CUBIC interpolation into a 30 fps
// clip of kDemoWalkCycles cycles. Rotations and root height loop
// exactly (the last frame equals the first); the root advances along +Z at
// kDemoWalkSpeed, so a looping player jumps back unless it carries root motion.
BvhData MakeDemoWalk();

}  // namespace armature
