// CrowdService: the gRPC adapter of crowd sessions (crowd_session), paced by
// its own FrameScheduler, counted in the server's CrowdTotals.
#pragma once

#include <memory>

#include "armature/v1/crowd.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/crowd/crowd_totals.h"
#include "server/rpc/limits.h"
#include "server/rpc/streams/frame_scheduler.h"
#include "server/rpc/streams/session_admission.h"
#include "server/rpc/streams/stream_admission.h"

namespace armature::server {

class CrowdServiceImpl final : public v1::CrowdService::CallbackService {
 public:
  CrowdServiceImpl(AssetStore& store, const Limits& limits, std::shared_ptr<SessionAdmission> sessions,
                   std::shared_ptr<StreamAdmission> streams, std::shared_ptr<CrowdTotals> totals)
      : store_(store),
        limits_(limits),
        sessions_(std::move(sessions)),
        streams_(std::move(streams)),
        totals_(std::move(totals)) {}

  grpc::ServerBidiReactor<v1::CrowdCommand, v1::CrowdFrame>* CrowdSession(
      grpc::CallbackServerContext* context) override;
  grpc::ServerWriteReactor<v1::CrowdFrame>* WatchCrowd(grpc::CallbackServerContext* context,
                                                       const v1::WatchCrowdRequest* request) override;

 private:
  AssetStore& store_;
  const Limits& limits_;
  std::shared_ptr<SessionAdmission> sessions_;  // shared with the other session kinds
  std::shared_ptr<StreamAdmission> streams_;    // shared with the other streaming RPCs
  std::shared_ptr<CrowdTotals> totals_;
  FrameScheduler scheduler_;  // paces the crowds' ticks
};

}  // namespace armature::server
