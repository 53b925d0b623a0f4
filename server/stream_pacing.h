// How a real-time stream plays its clip.
#pragma once

namespace armature::server {

// Validated pacing of a stream (see ValidatePacing).
struct StreamPacing {
  double fps = 30;
  double speed = 1;
  bool loop = false;
  double start_time = 0;
  double duration = 0;  // wall-clock seconds; 0 = at the clip's end (or never when looping)
};

}  // namespace armature::server
