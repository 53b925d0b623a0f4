// Internal: SampleClip's argument checks.
#pragma once

#include <cstddef>

#include "armature/base/status.h"
#include "armature/engine/anim/clip.h"

namespace armature::anim_internal {

// The clip has a skeleton and a track per joint, `out_size` is the joint
// count, the time is finite, and the options' enums are known values.
Status CheckSampleArguments(const Clip& clip, double time, const SampleOptions& options, size_t out_size);

}  // namespace armature::anim_internal
