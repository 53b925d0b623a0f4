// PoseService: clip evaluation, real-time pose streams, playback sessions and
// forward kinematics.
#pragma once

#include <memory>

#include "armature/v1/poses.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/call_progress.h"
#include "server/rpc/frame_scheduler.h"
#include "server/rpc/heavy_call_pool.h"
#include "server/rpc/limits.h"
#include "server/rpc/reply_size.h"
#include "server/rpc/session_admission.h"
#include "server/rpc/stream_admission.h"
#include "server/rpc/work_budget.h"

namespace armature::server {

class PoseServiceImpl final : public v1::PoseService::CallbackService {
 public:
  PoseServiceImpl(AssetStore& store, const Limits& limits, std::shared_ptr<SessionAdmission> sessions,
                  std::shared_ptr<StreamAdmission> streams, std::shared_ptr<HeavyCallPool> heavy)
      : store_(store), limits_(limits), sessions_(std::move(sessions)), streams_(std::move(streams)),
        heavy_(std::move(heavy)) {}

  grpc::ServerUnaryReactor* EvaluateClip(grpc::CallbackServerContext* context,
                                         const v1::EvaluateClipRequest* request,
                                         v1::EvaluateClipResponse* response) override;
  grpc::ServerUnaryReactor* EvaluateMotion(grpc::CallbackServerContext* context,
                                           const v1::EvaluateMotionRequest* request,
                                           v1::EvaluateMotionResponse* response) override;
  grpc::ServerWriteReactor<v1::PoseFrame>* StreamClip(grpc::CallbackServerContext* context,
                                                      const v1::StreamClipRequest* request) override;
  grpc::ServerBidiReactor<v1::PlaybackCommand, v1::PlaybackFrame>* PlaybackSession(
      grpc::CallbackServerContext* context) override;
  grpc::ServerUnaryReactor* ComputeFk(grpc::CallbackServerContext* context, const v1::ComputeFkRequest* request,
                                      v1::ComputeFkResponse* response) override;

 private:
  AssetStore& store_;
  const Limits& limits_;
  std::shared_ptr<SessionAdmission> sessions_;  // shared with the IK and deformation sessions
  std::shared_ptr<StreamAdmission> streams_;  // shared with the other streaming RPCs
  std::shared_ptr<HeavyCallPool> heavy_;      // EvaluateClip and EvaluateMotion beyond a few milliseconds
  FrameScheduler scheduler_;  // paces StreamClip and PlaybackSession
};

// What an evaluation costs (work_budget.h): times × the joints of the
// clip's skeleton, × the layers for a motion (its first layer's skeleton).
// An unknown clip costs 0 here; the handler reports it.
RequestWork EvaluateClipWork(const Catalog& catalog, const v1::EvaluateClipRequest& request);
RequestWork EvaluateMotionWork(const Catalog& catalog, const v1::EvaluateMotionRequest& request);

// The handlers' work, callable without gRPC (benchmarks, tests). The cost is
// checked against --max-request-work before any pose is computed; `progress`
// stops the loop over times at the call's deadline or cancellation. `encoding`
// is the answer's (reply_size.h): its size is bounded in it.
Status EvaluateClip(const Catalog& catalog, const Limits& limits, const v1::EvaluateClipRequest& request,
                    v1::EvaluateClipResponse* response, ReplyEncoding encoding = ReplyEncoding::kProtobuf,
                    CallProgress progress = {});
Status EvaluateMotion(const Catalog& catalog, const Limits& limits, const v1::EvaluateMotionRequest& request,
                      v1::EvaluateMotionResponse* response, ReplyEncoding encoding = ReplyEncoding::kProtobuf,
                      CallProgress progress = {});
Status ComputeFk(const Catalog& catalog, const v1::ComputeFkRequest& request, v1::ComputeFkResponse* response);

}  // namespace armature::server
