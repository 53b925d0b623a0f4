// AuthoringService: thin callback handlers; the work is in retarget_handler
// and create_clip_handler, and the result is stored by derived_clip.
#pragma once

#include "armature/v1/authoring.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"

namespace armature::server {

class AuthoringServiceImpl final : public v1::AuthoringService::CallbackService {
 public:
  AuthoringServiceImpl(AssetStore& store, const Limits& limits) : store_(store), limits_(limits) {}

  grpc::ServerUnaryReactor* RetargetClip(grpc::CallbackServerContext* context, const v1::RetargetClipRequest* request,
                                         v1::RetargetClipResponse* response) override;
  grpc::ServerUnaryReactor* CreateClip(grpc::CallbackServerContext* context, const v1::CreateClipRequest* request,
                                       v1::CreateClipResponse* response) override;

 private:
  AssetStore& store_;
  const Limits& limits_;
};

}  // namespace armature::server
