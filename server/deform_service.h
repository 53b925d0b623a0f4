// DeformService: Laplacian / ARAP mesh editing, one-shot and as a session.
#pragma once

#include <memory>

#include "armature/v1/deform.grpc.pb.h"
#include "server/asset_store.h"
#include "server/limits.h"
#include "server/session_admission.h"

namespace armature::server {

class DeformServiceImpl final : public v1::DeformService::CallbackService {
 public:
  DeformServiceImpl(AssetStore& store, const Limits& limits, std::shared_ptr<SessionAdmission> sessions)
      : store_(store), limits_(limits), sessions_(std::move(sessions)) {}

  grpc::ServerUnaryReactor* Deform(grpc::CallbackServerContext* context, const v1::DeformRequest* request,
                                   v1::DeformResponse* response) override;
  grpc::ServerBidiReactor<v1::DeformSessionRequest, v1::DeformResponse>* DeformSession(
      grpc::CallbackServerContext* context) override;

 private:
  AssetStore& store_;
  const Limits& limits_;
  std::shared_ptr<SessionAdmission> sessions_;  // shared with the other session kinds
};

// The unary handler's work, callable without gRPC.
Status Deform(const Catalog& catalog, const Limits& limits, const v1::DeformRequest& request,
              v1::DeformResponse* response);

}  // namespace armature::server
