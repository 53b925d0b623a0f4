// One playback session's logic, without gRPC: the first message (`start`)
// sets the skeleton, fps, duration and first play; later commands wait in a
// queue until the next frame, which applies them, or holds those whose `at`
// is later until the first frame at or after it; frame k shows session time
// k/fps.
// The pacing (frame k due at start + k/fps) and the transport are
// SessionReactor<PlaybackSession>'s (server/rpc/streams/session_reactor.h).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "armature/v1/playback.pb.h"
#include "server/assets/catalog.h"
#include "server/pose/playback_commands.h"
#include "server/rpc/call_stop.h"
#include "server/rpc/limits.h"
#include "server/rpc/streams/session_kind.h"

namespace armature::server {

class PlaybackSession {
 public:
  using Request = v1::PlaybackCommand;
  using Frame = v1::PlaybackFrame;  // a paced session: frames come on a clock, not per message
  static constexpr SessionKind kKind = SessionKind::kPlayback;
  static constexpr const char* kName = "PlaybackSession";
  // Commands held for a later `at`: a client cannot make the server keep more.
  static constexpr size_t kMaxWaiting = 64;

  PlaybackSession(CatalogSource catalog, const Limits& limits) : catalog_(std::move(catalog)), limits_(limits) {}
  ~PlaybackSession();

  // The first message; errors name the field ("start.fps: …").
  Status Start(const CallStop& call, const Request& first);
  double fps() const { return setup_.fps; }
  uint64_t frames() const { return frames_; }  // filled so far: the next frame's index

  // A later command, kept until the next frame.
  void Queue(Request command) { queued_.emplace_back(++commands_, std::move(command)); }
  size_t queued() const { return queued_.size(); }
  // Empties the queue, holding the commands whose `at` is after the next
  // frame's time, then applies every command due by then: by `at`, then in
  // the order sent. The first refused ends the session, named by its message
  // ("message 3: play.clip: …", "message 4: at: …").
  Status ApplyQueued();
  size_t waiting() const { return waiting_.size(); }  // held for a later `at`
  // Frame frames(), then the playback advanced by 1/fps; false (and no frame)
  // when the session is over: its duration played or, without one, the
  // client closed its side (`closed`). A failed fill is INTERNAL.
  StatusOr<bool> NextFrame(bool closed, Frame* frame);

 private:
  CatalogSource catalog_;
  const Limits& limits_;
  PlaybackSetup setup_;
  std::unique_ptr<Playback> playback_;
  // Moves the queue into waiting_, each keyed by when it takes effect.
  Status HoldQueued(double now);
  // Applies the waiting commands due at session time `now`.
  Status ApplyDue(double now);

  std::map<uint64_t, std::string> names_;
  std::vector<std::pair<uint64_t, Request>> queued_;        // (message number, command)
  std::map<std::pair<double, uint64_t>, Request> waiting_;  // (effective time, message number) → command
  uint64_t commands_ = 0;                                   // read after the start
  uint64_t frames_ = 0;
  MotionWorkspace motion_ws_;
  PoseWorkspace pose_ws_;
};

}  // namespace armature::server
