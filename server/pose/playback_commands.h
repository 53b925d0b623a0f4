// PlaybackSession's messages ↔ the engine's Playback: commands applied,
// frames filled. Callable without gRPC (the reactor paces and transports).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "armature/engine/anim/playback.h"
#include "armature/v1/playback.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"
#include "server/rpc/convert/pose_convert.h"

namespace armature::server {

// A session's state beside the playback: what the start fixed.
struct PlaybackSetup {
  PartRef<NamedSkeleton> skeleton;
  double fps = 30;
  double duration = 0;
  v1::Space space = v1::LOCAL;
  std::vector<int> joints;
};

// The start message: the skeleton, fps (default 30), duration, space,
// joints, and the first play (id 0) applied to `playback` (made here).
// Errors are INVALID_ARGUMENT / NOT_FOUND naming the field ("start.fps: …").
StatusOr<PlaybackSetup> StartPlayback(const Catalog& catalog, const Limits& limits, const v1::PlaybackStart& start,
                                      std::unique_ptr<Playback>& playback, std::map<uint64_t, std::string>& names);

// A later command (the `id`-th message after the start); errors name the
// command's field ("set_layer.layer: 3 is out of range …"); a second start
// is refused. `names` keeps the name of each play by id.
Status ApplyPlaybackCommand(const Catalog& catalog, const Limits& limits, const v1::PlaybackCommand& command,
                            uint64_t id, Playback& playback, std::map<uint64_t, std::string>& names);

// The work each second of the session now asks for: the layers of every
// motion playing × the skeleton's joints × fps, against --max-stream-work
// (RESOURCE_EXHAUSTED naming `field`, the budget and the cost). Checked after
// each play, before a frame of it is computed.
Status ValidatePlaybackWork(const PlaybackSetup& setup, const Playback& playback, const Limits& limits,
                            const std::string& field);

// Frame `index`: session time index/fps, the playing motions, the pose (and,
// for the first frame, the joints and skeleton name). Does not advance.
Status FillPlaybackFrame(const PlaybackSetup& setup, const Playback& playback,
                         const std::map<uint64_t, std::string>& names, uint64_t index, MotionWorkspace& motion_ws,
                         PoseWorkspace& pose_ws, v1::PlaybackFrame& frame);

}  // namespace armature::server
