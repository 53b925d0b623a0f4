// BVH (Biovision Hierarchy) motion capture: reader and writer.
#pragma once

#include <string>
#include <cstdint>
#include <string_view>
#include <vector>

#include "armature/engine/anim/clip.h"
#include "armature/engine/io/import_limits.h"
#include "armature/engine/anim/skeleton.h"
#include "armature/base/status.h"

namespace armature {

struct BvhData {
  std::shared_ptr<const Skeleton> skeleton;
  std::shared_ptr<const Clip> clip;
  std::vector<std::string> warnings;  // what was repaired or ignored, e.g. extra frame lines
};

// Parses a whole BVH file. Channels compose in the order listed
// (`Zrotation Xrotation Yrotation` is Rz·Rx·Ry in the joint's frame); a
// joint's translation is its OFFSET plus its position channels. Frame i is at
// time i·FrameTime. Only joints with channels get tracks. Frame lines beyond
// the declared "Frames:" are ignored with a warning; fewer is an error.
// Errors are INVALID_ARGUMENT naming the line, e.g. "line 12: expected
// OFFSET, found 'CHANNELS'" (joint names must be UTF-8); a count over
// `limits` (max_clip_frames, max_clip_keys) is RESOURCE_EXHAUSTED, found at
// the "Frames:" line before any frame is stored.
StatusOr<BvhData> ParseBvh(std::string_view text, const ImportLimits& limits = {});

// Writes `clip` sampled at its frame times (frame_time, or 1/30 s when the
// clip has none) using each joint's channel list (a skeleton without channels
// gets Xposition Yposition Zposition Zrotation Xrotation Yrotation on roots
// and Zrotation Xrotation Yrotation elsewhere). Joints are written depth
// first; Euler angles follow the previous frame so curves stay continuous;
// values have six decimals. Scale and motion a joint has no channel for are
// dropped. Returns "" for a clip without a skeleton or with a track count
// that differs from it (Clip::Validate catches both), or with more than
// kMaxBvhExportFrames frames.
std::string WriteBvh(const Clip& clip);

// The frames the writer refuses beyond by default (an hour at 240 fps is 864000).
inline constexpr uint64_t kMaxBvhExportFrames = 1000000;

// The number of frames WriteBvh writes for `clip`: its frame_count when it
// has a frame_time, else duration at 30 fps plus one; saturates at
// UINT64_MAX for absurd time spans. Costs O(1), so a caller can refuse an
// export before any work.
uint64_t BvhExportFrameCount(const Clip& clip);

// An estimate of the size WriteBvh's output will have, in bytes (hierarchy
// plus ~11 bytes per value); saturates at UINT64_MAX.
uint64_t BvhExportByteEstimate(const Clip& clip);

// WriteBvh with errors: INVALID_ARGUMENT for a clip that does not match its
// skeleton, RESOURCE_EXHAUSTED when BvhExportFrameCount exceeds `max_frames`.
StatusOr<std::string> ExportBvh(const Clip& clip, uint64_t max_frames = kMaxBvhExportFrames);

}  // namespace armature
