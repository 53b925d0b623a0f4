// DeformSession: one drag session per call. The first message sets up the
// deformer (factored on `setups`, off gRPC's callback threads); each move is a
// back-substitution answered in order.
#pragma once

#include "armature/v1/deform.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/elastic_thread_pool.h"
#include "server/rpc/limits.h"
#include "server/rpc/session_admission.h"
#include "server/rpc/stream_admission.h"

namespace armature::server {

// The reactor for one session; it finishes itself with RESOURCE_EXHAUSTED
// when the session limits refuse it.
grpc::ServerBidiReactor<v1::DeformSessionRequest, v1::DeformResponse>* NewDeformSession(
    grpc::CallbackServerContext* context, AssetStore& store, const Limits& limits, SessionAdmission& sessions,
    StreamAdmission::Ticket stream, ElasticThreadPool& setups);

}  // namespace armature::server
