// Clips on other skeletons: a clip plays on any skeleton whose joints it
// has by name (the demo walk's BVH on the demo character's glTF skeleton).
// The one binding rule of skinning a mesh by a clip and of motion layers;
// ClipSamplingOntoJob (anim/compression/clip_sampling_job.h) plays a clip
// through such a map.
#pragma once

#include <span>
#include <string_view>
#include <vector>

#include "armature/base/status.h"
#include "armature/engine/anim/clip.h"
#include "armature/engine/anim/skeleton.h"
#include "armature/engine/math/transform.h"

namespace armature {

// Per joint of `target`: the joint of `source` with the same name (the
// identity when both are one skeleton). Joints of `source` that `target`
// lacks are ignored. When `source` lacks joints of `target`:
// INVALID_ARGUMENT "lacks 2 of the 19 joints of <target_label>: 'LeftHip',
// 'RightHip'" (the first five named, then "and N more"), for the caller to
// prefix with what `source` is.
Status MapJointsByName(const Skeleton& target, const Skeleton& source, std::string_view target_label,
                       std::vector<int>& out);

}  // namespace armature
