// DeformService: the gRPC adapter of Laplacian / ARAP mesh editing, one-shot
// (deform_handlers) and as a session (deform_session).
#pragma once

#include <memory>

#include <algorithm>
#include <thread>

#include "armature/v1/deform.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/deform/deformer_cache.h"
#include "server/rpc/work/elastic_thread_pool.h"
#include "server/rpc/limits.h"
#include "server/rpc/streams/session_admission.h"
#include "server/rpc/streams/stream_admission.h"

namespace armature::server {

class DeformServiceImpl final : public v1::DeformService::CallbackService {
 public:
  // `cache` serves the unary Deform (sessions keep their own deformer).
  DeformServiceImpl(AssetStore& store, const Limits& limits, std::shared_ptr<SessionAdmission> sessions,
                    std::shared_ptr<StreamAdmission> streams, std::shared_ptr<DeformerCache> cache)
      : store_(store),
        limits_(limits),
        sessions_(std::move(sessions)),
        streams_(std::move(streams)),
        cache_(std::move(cache)),
        solves_(std::max(4u, 2 * std::thread::hardware_concurrency())) {}

  grpc::ServerUnaryReactor* Deform(grpc::CallbackServerContext* context, const v1::DeformRequest* request,
                                   v1::DeformResponse* response) override;
  grpc::ServerBidiReactor<v1::DeformSessionRequest, v1::DeformResponse>* DeformSession(
      grpc::CallbackServerContext* context) override;

 private:
  AssetStore& store_;
  const Limits& limits_;
  std::shared_ptr<SessionAdmission> sessions_;  // shared with the other session kinds
  std::shared_ptr<StreamAdmission> streams_;    // shared with the other streaming RPCs
  std::shared_ptr<DeformerCache> cache_;
  // Factorizations take seconds on large meshes: they run here, not on
  // gRPC's callback threads, so other calls keep being served. Last member:
  // destroyed first, after the server drained, running what is queued.
  ElasticThreadPool solves_;
};

}  // namespace armature::server
