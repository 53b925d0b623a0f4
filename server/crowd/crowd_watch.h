// A read-only crowd (CrowdService.WatchCrowd, issue 31): a CrowdSession whose
// characters all come in the request, played by PacedStreamReactor as a
// server stream, which gRPC-Web can carry (it cannot stream requests). A
// refused character fails the call before the first frame, with its status
// naming the character, rather than going in a frame as in a session.
#pragma once

#include <memory>

#include "armature/base/status.h"
#include "armature/engine/anim/clip.h"
#include "armature/v1/crowd.pb.h"
#include "server/crowd/crowd_session.h"
#include "server/rpc/stream_pacing.h"

namespace armature::server {

class CrowdWatchPlan {
 public:
  using Frame = v1::CrowdFrame;

  // The crowd with every character added, and its pacing: start.fps until
  // start.duration or max_ticks (neither: until the client cancels).
  static StatusOr<CrowdWatchPlan> Make(CatalogSource catalog, const Limits& limits, std::shared_ptr<CrowdTotals> totals,
                                       const v1::WatchCrowdRequest& request);

  const StreamPacing& pacing() const { return pacing_; }
  // The session keeps its own time (tick / fps); the reactor's clip time is unused.
  double duration() const { return 1e9; }
  Status Fill(uint64_t index, double time, WrapMode wrap, Frame& frame);

 private:
  CrowdWatchPlan(std::unique_ptr<CrowdSession> session, StreamPacing pacing)
      : session_(std::move(session)), pacing_(pacing) {}

  std::unique_ptr<CrowdSession> session_;
  StreamPacing pacing_;
};

}  // namespace armature::server
