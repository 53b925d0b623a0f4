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

// The one place a crowd gets a clip's compressed form: compressed on first
// use and kept, per session, by the clip. (When the catalog holds each
// clip's CompressedClip, this returns it.)
class CrowdClipSource {
 public:
  // The clip's runtime form, as the store holds it (NamedClip::runtime).
  StatusOr<std::shared_ptr<const CompressedClip>> CompressedOf(const NamedClip& clip);
};

struct ResolvedCharacter {
  std::string clip_name, skeleton_name;
  std::shared_ptr<const CompressedClip> clip;
  CrowdCharacter numbers;  // id, time offset, speed, significance (its clip index is the ticker's)
};

StatusOr<ResolvedCharacter> ResolveCharacter(const Catalog& catalog, const v1::CrowdCharacter& message,
                                             CrowdClipSource& clips);

}  // namespace armature::server
