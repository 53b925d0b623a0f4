// A crowd command's character resolved against the catalog: its skeleton
// (or character: a skeleton with meshes), its clip's compressed form, and
// its numbers checked; or its motion bound (CrowdMotionPlans). Errors name
// the character ("character 7: clip: …", "character 7: motion.layers[0]: …").
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>

#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/anim/crowd/crowd_ticker.h"
#include "armature/engine/anim/motion.h"
#include "armature/v1/crowd.pb.h"
#include "server/assets/catalog.h"
#include "server/crowd/crowd_motion_plans.h"

namespace armature::server {

struct ResolvedCharacter {
  std::string clip_name, skeleton_name;
  std::shared_ptr<const CompressedClip> clip;  // or
  std::shared_ptr<const MotionPlan> motion;    // a motion (clip_name: "motion:" and its layers' clips)
  CrowdCharacter numbers;                      // id, time offset, speed, significance (its clip index is the ticker's)
};

// A command's character resolved against the catalog; its clip is the
// store's runtime form (NamedClip::runtime), shared by every session. A
// motion is bound through `motions`; exactly one of clip and motion is set.
StatusOr<ResolvedCharacter> ResolveCharacter(const Catalog& catalog, const v1::CrowdCharacter& message,
                                             CrowdMotionPlans& motions);

}  // namespace armature::server
