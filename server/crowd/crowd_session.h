// One crowd session's logic, without gRPC (issue 31): the first message
// (`start`) sets the fps, budget and sharing; later commands add, update and
// remove characters, applied before the next tick. A refused command does
// not end the session: its error, naming the character, goes in the next
// frame. Tick k shows session time k/fps with the poses CrowdTicker updates.
// The pacing and the transport are SessionReactor<CrowdSession>'s.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include "armature/engine/anim/crowd/crowd_ticker.h"
#include "armature/v1/crowd.pb.h"
#include "server/assets/catalog.h"
#include "server/crowd/crowd_character.h"
#include "server/crowd/crowd_motion_plans.h"
#include "server/crowd/crowd_totals.h"
#include "server/rpc/call_stop.h"
#include "server/rpc/limits.h"
#include "server/rpc/streams/session_kind.h"

namespace armature::server {

class CrowdSession {
 public:
  using Request = v1::CrowdCommand;
  using Frame = v1::CrowdFrame;
  static constexpr SessionKind kKind = SessionKind::kCrowd;
  static constexpr const char* kName = "CrowdSession";
  static constexpr size_t kMaxQueued = 16384;  // commands read before a tick takes them (SessionReactor)
  static constexpr size_t kMaxErrors = 256;    // refusals kept for one frame; more are counted in the last

  CrowdSession(CatalogSource catalog, const Limits& limits, std::shared_ptr<CrowdTotals> totals)
      : catalog_(std::move(catalog)), limits_(limits), totals_(std::move(totals)), motions_(limits) {}
  ~CrowdSession();

  // The first message; errors name the field ("start.fps: …") and end the call.
  Status Start(const CallStop& call, const Request& first);
  double fps() const { return fps_; }
  // A client that stops reading is dropped after this long (--crowd-write-timeout-seconds, SessionReactor).
  double write_timeout_seconds() const { return limits_.crowd_write_timeout_seconds; }
  uint64_t frames() const { return frames_; }

  void Queue(Request command) { queued_.emplace_back(++commands_, std::move(command)); }
  size_t queued() const { return queued_.size(); }
  // Applies the queued commands in order; refusals become the next frame's errors.
  Status ApplyQueued();
  // Tick frames(); false when the duration has played or, without one, the client closed its side.
  StatusOr<bool> NextFrame(bool closed, Frame* frame);
  // The first command refused since the start (OK: none); a read-only watch fails on it.
  const Status& first_refusal() const { return first_refusal_; }

 private:
  Status Apply(const Catalog& catalog, const Request& command);
  Status Add(const Catalog& catalog, const v1::CrowdCharacter& message);
  Status Update(const Catalog& catalog, const v1::CrowdCharacter& message);
  Status Remove(uint32_t id);
  // The ticker's clip (or motion) index for a resolved character; a new one gets a layout sent in the next frame.
  StatusOr<uint32_t> ClipIndexOf(const ResolvedCharacter& resolved);
  void Refuse(uint64_t number, uint32_t id, const Status& status);
  void FillLayouts(Frame* frame);

  CatalogSource catalog_;
  const Limits& limits_;
  std::shared_ptr<CrowdTotals> totals_;
  CrowdMotionPlans motions_;  // bound once per distinct motion
  double fps_ = 30, budget_ms_ = 0, duration_ = 0;
  std::unique_ptr<CrowdTicker> ticker_;
  std::vector<std::pair<std::string, std::string>> clip_names_;  // per ticker clip: (clip, skeleton)
  size_t layouts_sent_ = 0;
  std::unordered_map<uint32_t, v1::CrowdRoot> roots_;  // the characters held, with their roots
  std::vector<std::pair<uint64_t, Request>> queued_;   // (message number, command)
  std::vector<v1::CrowdError> errors_;
  Status first_refusal_;
  uint64_t commands_ = 0, frames_ = 0, errors_dropped_ = 0;
  std::chrono::steady_clock::time_point start_;
  CrowdTick tick_;
};

}  // namespace armature::server
