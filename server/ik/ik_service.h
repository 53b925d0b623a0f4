// IkService: the gRPC adapter of one-shot inverse kinematics solves
// (ik_handlers) and interactive sessions (ik_session).
#pragma once

#include <memory>

#include "armature/v1/ik.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"
#include "server/rpc/streams/session_admission.h"
#include "server/rpc/streams/stream_admission.h"

namespace armature::server {

class IkServiceImpl final : public v1::IkService::CallbackService {
 public:
  IkServiceImpl(AssetStore& store, const Limits& limits, std::shared_ptr<SessionAdmission> sessions,
                std::shared_ptr<StreamAdmission> streams)
      : store_(store), limits_(limits), sessions_(std::move(sessions)), streams_(std::move(streams)) {}

  grpc::ServerUnaryReactor* SolveIk(grpc::CallbackServerContext* context, const v1::SolveIkRequest* request,
                                    v1::SolveIkResponse* response) override;
  grpc::ServerBidiReactor<v1::IkSessionRequest, v1::SolveIkResponse>* IkSession(
      grpc::CallbackServerContext* context) override;

 private:
  AssetStore& store_;
  const Limits& limits_;
  std::shared_ptr<SessionAdmission> sessions_;  // shared with the other session kinds
  std::shared_ptr<StreamAdmission> streams_;    // shared with the other streaming RPCs
};

}  // namespace armature::server
