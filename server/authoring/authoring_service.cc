#include "server/authoring/authoring_service.h"

#include "armature/v1/authoring.pb.h"

#include "server/authoring/create_clip_handler.h"
#include "server/authoring/retarget_handler.h"
#include "server/rpc/call_guard.h"

namespace armature::server {

// authoring.proto holds only the service, so nothing would link its
// descriptor in from the static proto library; the auth gate, reflection and
// the gateway look the service up by name.
extern const void* const kAuthoringProtoDescriptor;
const void* const kAuthoringProtoDescriptor = &::descriptor_table_armature_2fv1_2fauthoring_2eproto;

grpc::ServerUnaryReactor* AuthoringServiceImpl::RetargetClip(grpc::CallbackServerContext* context,
                                                             const v1::RetargetClipRequest* request,
                                                             v1::RetargetClipResponse* response) {
  return RunUnary(context, "RetargetClip",
                  [&]() -> Status { return server::RetargetClip(store_, limits_, *request, response); });
}

grpc::ServerUnaryReactor* AuthoringServiceImpl::CreateClip(grpc::CallbackServerContext* context,
                                                           const v1::CreateClipRequest* request,
                                                           v1::CreateClipResponse* response) {
  return RunUnary(context, "CreateClip",
                  [&]() -> Status { return server::CreateClip(store_, limits_, *request, response); });
}

}  // namespace armature::server
