#include "server/deform/deform_service.h"

#include <optional>
#include <string>

#include "server/rpc/call_guard.h"
#include "server/rpc/grpc_status.h"
#include "server/deform/deform_session_reactor.h"
#include "server/deform/mesh_deformer.h"

namespace armature::server {

Status Deform(DeformerCache& cache, const std::shared_ptr<const Catalog>& catalog, const Limits& limits,
              const v1::DeformRequest& request, v1::DeformResponse* response) {
  std::vector<uint32_t> handles;
  std::vector<double> positions;
  ARMATURE_RETURN_IF_ERROR(SplitHandles(request, &handles, &positions));
  auto deformer = cache.Get(catalog, limits, SetupOf(request), std::move(handles));
  if (!deformer.ok()) return deformer.status();
  return (*deformer)->SolveFresh(positions, "handles", response);
}

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
  return MakeReactor<grpc::ServerBidiReactor<v1::DeformSessionRequest, v1::DeformResponse>>(context, "DeformSession", [&]() -> grpc::ServerBidiReactor<v1::DeformSessionRequest, v1::DeformResponse>* {
    using Base = grpc::ServerBidiReactor<v1::DeformSessionRequest, v1::DeformResponse>;
    auto stream = streams_->Admit(*context, "DeformSession");
    if (!stream.ok()) return new FinishedReactor<Base>(stream.status());
    return NewDeformSession(context, store_, limits_, *sessions_, std::move(*stream), solves_);
  });
}

}  // namespace armature::server
