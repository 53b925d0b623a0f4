// PoseService: the gRPC adapter of clip evaluation and forward kinematics
// (pose_handlers), real-time pose streams and playback sessions
// (playback_session).
#pragma once

#include <memory>

#include "armature/v1/poses.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"
#include "server/rpc/stream_pacing.h"
#include "server/rpc/streams/frame_scheduler.h"
#include "server/rpc/streams/session_admission.h"
#include "server/rpc/streams/stream_admission.h"
#include "server/rpc/work/heavy_call_pool.h"

namespace armature::server {

class PoseServiceImpl final : public v1::PoseService::CallbackService {
 public:
  PoseServiceImpl(AssetStore& store, const Limits& limits, std::shared_ptr<SessionAdmission> sessions,
                  std::shared_ptr<StreamAdmission> streams, std::shared_ptr<HeavyCallPool> heavy)
      : store_(store),
        limits_(limits),
        sessions_(std::move(sessions)),
        streams_(std::move(streams)),
        heavy_(std::move(heavy)) {}

  grpc::ServerUnaryReactor* EvaluateClip(grpc::CallbackServerContext* context, const v1::EvaluateClipRequest* request,
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
  // A stream of `plan`'s frames, or one that fails with its error.
  template <class Plan>
  grpc::ServerWriteReactor<typename Plan::Frame>* Play(StatusOr<Plan> plan, StreamPacing pacing,
                                                       StreamAdmission::Ticket stream);

  AssetStore& store_;
  const Limits& limits_;
  std::shared_ptr<SessionAdmission> sessions_;  // shared with the IK and deformation sessions
  std::shared_ptr<StreamAdmission> streams_;    // shared with the other streaming RPCs
  std::shared_ptr<HeavyCallPool> heavy_;        // EvaluateClip and EvaluateMotion beyond a few milliseconds
  FrameScheduler scheduler_;                    // paces StreamClip and PlaybackSession
};

}  // namespace armature::server
