#include "server/deform/deform_service.h"

#include <memory>

#include "server/deform/deform_handlers.h"
#include "server/deform/deform_session.h"
#include "server/rpc/call_guard.h"
#include "server/rpc/grpc_status.h"
#include "server/rpc/streams/session_reactor.h"

namespace armature::server {

grpc::ServerUnaryReactor* DeformServiceImpl::Deform(grpc::CallbackServerContext* context,
                                                    const v1::DeformRequest* request, v1::DeformResponse* response) {
  grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
  try {
    solves_.Enqueue([this, context, reactor, request, response, catalog = store_.Snapshot()] {
      reactor->Finish(ToGrpcStatus(
          Guarded(context, "Deform", [&] { return server::Deform(*cache_, catalog, limits_, *request, response); })));
    });
  } catch (...) {  // could not even queue it
    reactor->Finish(ToGrpcStatus(StatusOfCurrentException(context, "Deform")));
  }
  return reactor;
}

grpc::ServerBidiReactor<v1::DeformSessionRequest, v1::DeformResponse>* DeformServiceImpl::DeformSession(
    grpc::CallbackServerContext* context) {
  using Base = grpc::ServerBidiReactor<v1::DeformSessionRequest, v1::DeformResponse>;
  return MakeReactor<Base>(context, "DeformSession", [&]() -> Base* {
    auto stream = streams_->Admit(*context, "DeformSession");
    if (!stream.ok()) return new FinishedReactor<Base>(stream.status());
    auto session = std::make_unique<server::DeformSession>([&store = store_] { return store.Snapshot(); }, limits_);
    // The setup factors: on solves_, off gRPC's callback threads.
    return new SessionReactor<server::DeformSession>(context, *sessions_, std::move(*stream), std::move(session),
                                                     {.start_pool = &solves_});
  });
}

}  // namespace armature::server
