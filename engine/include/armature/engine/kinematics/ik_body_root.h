// Which joint carries the body: the one IK keeps where it stands by default.
// A skeleton's topmost node is not always it: a Mixamo character exported to
// glTF has `Armature`, a still node at scale 0.01, above `mixamorig:Hips`, and
// keeping `Armature` fixed lets the hips turn and the feet slide.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "armature/engine/anim/clip.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/anim/skeleton.h"

namespace armature {

// Per joint, 1 where the joint may carry the body: some clip of `clips`
// (clips of `skeleton`, joint for joint) moves its translation, or it is the
// parent of the legs (the lowest common ancestor of both thighs, read by
// name as retargeting reads them, FindBodyParts).
std::vector<uint8_t> BodyRootCandidates(const Skeleton& skeleton, std::span<const CompressedClip* const> clips);

// The body root above `joint`: walking down `joint`'s ancestors from the
// top, the first candidate; the topmost ancestor when none is (or when
// `candidates` is empty). `joint` itself is never its own body root unless
// it is the top.
int BodyRootAbove(const Skeleton& skeleton, int joint, std::span<const uint8_t> candidates);

}  // namespace armature
