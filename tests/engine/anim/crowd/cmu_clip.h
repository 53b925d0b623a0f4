// The crowd tests' clip: CMU 01_01 from ../shared/data, compressed once
// (null when the data is absent).
#pragma once

#include <memory>

#include "armature/engine/anim/compression/compressed_clip.h"
#include "../../testing/shared_clips.h"

namespace armature {

inline std::shared_ptr<const CompressedClip> Cmu() {
  static const std::shared_ptr<const CompressedClip> clip = [] {
    for (const test_util::SharedClip& c : test_util::LoadSharedClips())
      if (c.name == "bvh/cmu_01_01.bvh") return *CompressClip(c.clip);
    return std::shared_ptr<const CompressedClip>();
  }();
  return clip;
}

}  // namespace armature
