// BVH (Biovision Hierarchy) motion capture: reader and writer.
#pragma once

#include <string>
#include <string_view>

#include "armature/engine/clip.h"
#include "armature/engine/skeleton.h"
#include "armature/engine/status.h"

namespace armature {

struct BvhData {
  std::shared_ptr<const Skeleton> skeleton;
  std::shared_ptr<const Clip> clip;
};

// Parses a whole BVH file. Channels compose in the order listed
// (`Zrotation Xrotation Yrotation` is Rz·Rx·Ry in the joint's frame); a
// joint's translation is its OFFSET plus its position channels. Frame i is at
// time i·FrameTime. Errors are INVALID_ARGUMENT naming the line, e.g.
// "line 12: expected OFFSET, found 'CHANNELS'".
StatusOr<BvhData> ParseBvh(std::string_view text);

// Writes `clip` sampled at its frame times (frame_time, or 1/30 s when the
// clip has none) using each joint's channel list (a skeleton without channels
// gets Xposition Yposition Zposition Zrotation Xrotation Yrotation on roots
// and Zrotation Xrotation Yrotation elsewhere). Joints are written depth
// first; Euler angles follow the previous frame so curves stay continuous;
// values have six decimals. Scale and motion a joint has no channel for are
// dropped. Returns "" for a clip without a skeleton or with a track count
// that differs from it (Clip::Validate catches both).
std::string WriteBvh(const Clip& clip);

}  // namespace armature
