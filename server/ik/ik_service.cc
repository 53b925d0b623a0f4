#include "server/ik/ik_service.h"

#include <memory>

#include "server/ik/ik_handlers.h"
#include "server/ik/ik_session.h"
#include "server/rpc/call_guard.h"
#include "server/rpc/grpc_status.h"
#include "server/rpc/streams/session_reactor.h"

namespace armature::server {

grpc::ServerUnaryReactor* IkServiceImpl::SolveIk(grpc::CallbackServerContext* context,
                                                 const v1::SolveIkRequest* request, v1::SolveIkResponse* response) {
  return RunUnary(context, "SolveIk", [&]() -> Status {
    return server::SolveIk(*store_.Snapshot(), limits_, *request, response, CallStopOf(*context));
  });
}

grpc::ServerBidiReactor<v1::IkSessionRequest, v1::SolveIkResponse>* IkServiceImpl::IkSession(
    grpc::CallbackServerContext* context) {
  using Base = grpc::ServerBidiReactor<v1::IkSessionRequest, v1::SolveIkResponse>;
  return MakeReactor<Base>(context, "IkSession", [&]() -> Base* {
    auto stream = streams_->Admit(*context, "IkSession");
    if (!stream.ok()) return new FinishedReactor<Base>(stream.status());
    auto session = std::make_unique<server::IkSession>([&store = store_] { return store.Snapshot(); }, limits_);
    return new SessionReactor<server::IkSession>(context, *sessions_, std::move(*stream), std::move(session));
  });
}

}  // namespace armature::server
