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

// The pacing fields of a stream request (StreamClipRequest,
// StreamSkinnedMeshRequest), not yet validated.
template <class Request>
StreamPacing PacingOf(const Request& r) {
  return {r.fps(), r.speed(), r.loop(), r.start_time(), r.duration()};
}

}  // namespace armature::server
