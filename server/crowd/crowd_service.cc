#include "server/crowd/crowd_service.h"

#include <memory>

#include "server/crowd/crowd_session.h"
#include "server/crowd/crowd_watch.h"
#include "server/rpc/call_guard.h"
#include "server/rpc/streams/paced_stream_reactor.h"
#include "server/rpc/streams/session_reactor.h"

namespace armature::server {

grpc::ServerBidiReactor<v1::CrowdCommand, v1::CrowdFrame>* CrowdServiceImpl::CrowdSession(
    grpc::CallbackServerContext* context) {
  using Base = grpc::ServerBidiReactor<v1::CrowdCommand, v1::CrowdFrame>;
  return MakeReactor<Base>(context, "CrowdSession", [&]() -> Base* {
    auto stream = streams_->Admit(*context, "CrowdSession");
    if (!stream.ok()) return new FinishedReactor<Base>(stream.status());
    auto session =
        std::make_unique<server::CrowdSession>([&store = store_] { return store.Snapshot(); }, limits_, totals_);
    return new SessionReactor<server::CrowdSession>(context, *sessions_, std::move(*stream), std::move(session),
                                                    {.scheduler = &scheduler_});
  });
}

grpc::ServerWriteReactor<v1::CrowdFrame>* CrowdServiceImpl::WatchCrowd(grpc::CallbackServerContext* context,
                                                                       const v1::WatchCrowdRequest* request) {
  using Base = grpc::ServerWriteReactor<v1::CrowdFrame>;
  return MakeReactor<Base>(context, "WatchCrowd", [&]() -> Base* {
    auto stream = streams_->Admit(*context, "WatchCrowd");
    if (!stream.ok()) return new FailedStream<v1::CrowdFrame>(stream.status());
    auto plan = CrowdWatchPlan::Make([&store = store_] { return store.Snapshot(); }, limits_, totals_, *request);
    if (!plan.ok()) return new FailedStream<v1::CrowdFrame>(plan.status());
    const StreamPacing pacing = plan->pacing();
    return new PacedStreamReactor<CrowdWatchPlan>(scheduler_, pacing, std::move(*plan), std::move(*stream));
  });
}

}  // namespace armature::server
