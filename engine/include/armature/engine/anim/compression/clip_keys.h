// A compressed clip back as keys (a Clip), for what needs keys rather than
// samples: export, and joint tracks read as tracks. An exact clip gives its
// stored keys; a lossy one a key per frame of its grid (CompressedClip::frames)
// for each part the source animates, sampled by ClipSamplingJob, LINEAR.
#pragma once

#include <memory>

#include "armature/base/status.h"
#include "armature/engine/anim/clip.h"
#include "armature/engine/anim/compression/compressed_clip.h"

namespace armature {

StatusOr<std::shared_ptr<const Clip>> ClipKeysOf(const CompressedClip& clip);

}  // namespace armature
