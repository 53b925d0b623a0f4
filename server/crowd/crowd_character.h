// A crowd command's character resolved against the catalog: its skeleton
// (or character: a skeleton with meshes), its clip's compressed form, and
// its numbers checked. Errors name the character ("character 7: clip: …").
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>

#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/anim/crowd/crowd_ticker.h"
#include "armature/v1/crowd.pb.h"
#include "server/assets/catalog.h"

namespace armature::server {

struct ResolvedCharacter {
  std::string clip_name, skeleton_name;
  std::shared_ptr<const CompressedClip> clip;
  CrowdCharacter numbers;  // id, time offset, speed, significance (its clip index is the ticker's)
};

// A command's character resolved against the catalog; its clip is the
// store's runtime form (NamedClip::runtime), shared by every session.
StatusOr<ResolvedCharacter> ResolveCharacter(const Catalog& catalog, const v1::CrowdCharacter& message);

}  // namespace armature::server
