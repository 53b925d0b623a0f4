// One playback session (PoseService.PlaybackSession): a bidirectional stream
// whose reads (commands) and paced writes (frames) run side by side. Frame k
// is due at start + k/fps (the FrameScheduler paces it, as PacedStreamReactor
// does for StreamClip) and is filled when frame k−1's write is done, applying
// the commands read until then. Commands wait in a short queue; when it is
// full, reading pauses until the next frame takes them (no unbounded memory).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "armature/v1/poses.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/pose/playback_commands.h"
#include "server/rpc/frame_scheduler.h"
#include "server/rpc/limits.h"
#include "server/rpc/session_admission.h"
#include "server/rpc/stream_admission.h"

namespace armature::server {

class PlaybackSessionReactor final : public grpc::ServerBidiReactor<v1::PlaybackCommand, v1::PlaybackFrame> {
 public:
  // When `sessions` refuses the client a place, the stream ends at once with
  // its RESOURCE_EXHAUSTED.
  PlaybackSessionReactor(grpc::CallbackServerContext* context, AssetStore& store, const Limits& limits,
                         FrameScheduler& scheduler, SessionAdmission& sessions, StreamAdmission::Ticket stream);

  void OnReadDone(bool ok) override;
  void OnWriteDone(bool ok) override;
  void OnCancel() override;
  void OnDone() override;

  static constexpr size_t kMaxQueuedCommands = 64;

 private:
  // Runs `fn` with mu_ held, inside the callback's exception boundary.
  void Guarded(const std::function<void()>& fn);
  // Each called with mu_ held.
  void ReadDone(bool ok);
  void WriteDone(bool ok);
  bool FillNext();  // applies the queued commands and fills frame_; false when the stream ended instead
  void Write();
  void ReadNext();
  void End(grpc::Status status);  // finishes once (after a write in flight)

  void Unref();  // deleted when OnDone has run and no scheduled frame is pending

  grpc::CallbackServerContext* context_;
  AssetStore& store_;
  const Limits& limits_;
  FrameScheduler& scheduler_;
  StreamAdmission::Ticket stream_;   // this call's place among the client's streams
  SessionAdmission::Ticket ticket_;  // this session's place

  std::mutex mu_;
  std::atomic<int> refs_{1};  // OnDone's, plus one per scheduled frame
  bool started_ = false, reading_ = false, read_closed_ = false;
  bool write_pending_ = false, cancelled_ = false, finished_ = false, end_requested_ = false;
  grpc::Status end_status_;

  v1::PlaybackCommand request_;
  std::vector<std::pair<uint64_t, v1::PlaybackCommand>> queued_;  // (message number, command)
  uint64_t messages_ = 0;  // read after the start

  PlaybackSetup setup_;
  std::unique_ptr<Playback> playback_;
  std::map<uint64_t, std::string> names_;
  MotionWorkspace motion_ws_;
  PoseWorkspace pose_ws_;
  v1::PlaybackFrame frame_;
  uint64_t index_ = 0;  // frames filled
  std::chrono::steady_clock::time_point start_;
};

}  // namespace armature::server
