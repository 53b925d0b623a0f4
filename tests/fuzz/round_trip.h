// Shared by the writer fuzz targets: a clip written as BVH must read back
// with the same joints and frame count.
#pragma once

#include <cstdio>
#include <cstdlib>

#include "armature/engine/io/bvh.h"
#include "fuzz_limits.h"

namespace armature::fuzz {

inline void ExpectBvhRoundTrip(const Clip& clip) {
  if (BvhExportFrameCount(clip) > kMaxExportFrames) {
    if (ExportBvh(clip, kMaxExportFrames).ok()) std::abort();  // the cap must hold
    return;
  }
  auto text = ExportBvh(clip, kMaxExportFrames);
  if (!text.ok()) {
    std::fprintf(stderr, "export failed: %s\n", text.status().message().c_str());
    std::abort();
  }
  ImportLimits limits = Limits();
  limits.max_clip_frames = kMaxExportFrames;
  auto back = ParseBvh(*text, limits);
  if (!back.ok()) {
    std::fprintf(stderr, "re-parse failed: %s\n", back.status().message().c_str());
    std::abort();
  }
  // Names are compared by count only: the writer replaces what BVH cannot
  // hold (control characters, blanks at the ends, a trailing '{').
  if (back->skeleton->size() != clip.skeleton->size() || back->clip->frame_count != BvhExportFrameCount(clip))
    std::abort();
}

}  // namespace armature::fuzz
