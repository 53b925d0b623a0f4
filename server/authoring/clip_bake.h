// CreateClip's `bake`: a motion sampled at a fps into LINEAR keys.
#pragma once

#include <string>

#include "armature/base/status.h"
#include "armature/engine/anim/clip.h"
#include "armature/v1/clip_keys.pb.h"
#include "server/assets/catalog.h"
#include "server/rpc/limits.h"

namespace armature::server {

// Memory per joint and key of a bake: the clip as sampled (three key times,
// a rotation, a translation and a scale in doubles: 104), its .glb (two
// float times, a rotation and a translation: 36) and the clip as the store
// holds it (parsed, 72, and compiled, 36), held together while it is stored.
inline constexpr int kBakeBytesPerJointKey = 104 + 36 + 72 + 36;

struct BakedClip {
  Clip clip;             // on the motion's skeleton, every joint keyed
  std::string skeleton;  // that skeleton's name
};

// The motion bound as EvaluateMotion binds it (errors name "bake.motion…"),
// sampled at k / fps for k = 0, 1, … up to `duration`, plus `duration`.
// INVALID_ARGUMENT for a bad fps or duration, RESOURCE_EXHAUSTED naming
// --max-clip-frames when the keys would be more, or --max-upload-mb when the
// clip in memory would be (kBakeBytesPerJointKey).
StatusOr<BakedClip> BakeMotion(const Catalog& catalog, const Limits& limits, const v1::ClipBake& bake);

}  // namespace armature::server
