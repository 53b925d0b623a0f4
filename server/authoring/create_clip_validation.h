// CreateClip's keys checked and turned into the engine's tracks, in one
// place. Each failure is INVALID_ARGUMENT naming the entry, the joint, the
// key index and the problem ("tracks[2] (joint 'Head'): key 3: time 0.4 does
// not increase (key 2 is at 0.5)"), or RESOURCE_EXHAUSTED naming the flag.
#pragma once

#include <string>
#include <vector>

#include "armature/base/status.h"
#include "armature/engine/anim/clip.h"
#include "armature/v1/clip_keys.pb.h"
#include "server/rpc/limits.h"

namespace armature::server {

// One request entry, ready to put into a clip.
struct KeyedJoint {
  int joint = -1;       // index in the skeleton
  bool remove = false;  // no times (merge only): the stored track is deleted
  JointTrack track;     // rotations normalized; CUBIC tracks without tangents have none yet
};

// The 32-bit float at or below `t`: the time a key at `t` is stored at. glTF
// stores times as floats, and rounding down keeps each key in effect from
// its own time on (a STEP key included).
double StoredKeyTime(double t);

// Every entry of `request.tracks` against `skeleton` (named `skeleton_name`
// in errors): a known joint named once; times finite, >= 0 and strictly
// increasing, also as 32-bit floats; rotations (w, x, y, z) within 1e-3 of
// unit norm, or Euler degrees in a valid order; 3 values per key for
// translations and scales; tangents only on CUBIC tracks, sized like their
// channel; every value finite and within a 32-bit float's range (glTF
// stores floats); at most --max-clip-frames keys per track.
StatusOr<std::vector<KeyedJoint>> KeyedJointsFromRequest(const v1::CreateClipRequest& request, const Skeleton& skeleton,
                                                         const std::string& skeleton_name, const Limits& limits);

}  // namespace armature::server
