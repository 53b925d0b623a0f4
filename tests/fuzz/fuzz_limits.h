// Import limits for the fuzz targets: the engine's caps scaled down so that
// anything the caps govern stays far below libFuzzer's -malloc_limit_mb=512;
// an allocation over it then means memory that no cap governs (a bug).
#pragma once

#include "armature/engine/io/import_limits.h"

namespace armature::fuzz {

inline ImportLimits Limits() {
  ImportLimits l;
  l.max_clip_frames = 100000;
  l.max_clip_keys = 1 << 20;
  l.max_mesh_vertices = 1 << 20;
  l.max_morph_target_vertices = 1 << 22;
  l.max_accessor_values = 1 << 22;
  l.max_unbacked_accessor_bytes = 1 << 20;
  return l;
}

// Frames the writer round-trips fuzz clips up to.
inline constexpr uint64_t kMaxExportFrames = 20000;

}  // namespace armature::fuzz
