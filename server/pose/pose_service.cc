#include "server/pose/pose_service.h"

#include <memory>

#include "server/pose/playback_session.h"
#include "server/pose/pose_handlers.h"
#include "server/pose/clip_stream_plan.h"
#include "server/pose/motion_stream_plan.h"
#include "server/rpc/call_guard.h"
#include "server/rpc/convert/pose_convert.h"
#include "server/rpc/grpc_status.h"
#include "server/rpc/request_validation.h"
#include "server/rpc/streams/paced_stream_reactor.h"
#include "server/rpc/streams/session_reactor.h"

namespace armature::server {

grpc::ServerUnaryReactor* PoseServiceImpl::EvaluateClip(grpc::CallbackServerContext* context,
                                                        const v1::EvaluateClipRequest* request,
                                                        v1::EvaluateClipResponse* response) {
  auto catalog = store_.Snapshot();
  const int64_t cost = EvaluateClipWork(*catalog, *request).total();
  return heavy_->Run(context, "EvaluateClip", cost, [this, context, request, response, catalog] {
    return server::EvaluateClip(*catalog, limits_, *request, response, ReplyEncodingOf(*context),
                                CallProgress(*context, "EvaluateClip", "times"));
  });
}

grpc::ServerUnaryReactor* PoseServiceImpl::EvaluateMotion(grpc::CallbackServerContext* context,
                                                          const v1::EvaluateMotionRequest* request,
                                                          v1::EvaluateMotionResponse* response) {
  auto catalog = store_.Snapshot();
  const int64_t cost = EvaluateMotionWork(*catalog, *request).total();
  return heavy_->Run(context, "EvaluateMotion", cost, [this, context, request, response, catalog] {
    return server::EvaluateMotion(*catalog, limits_, *request, response, ReplyEncodingOf(*context),
                                  CallProgress(*context, "EvaluateMotion", "times"));
  });
}

grpc::ServerUnaryReactor* PoseServiceImpl::ComputeFk(grpc::CallbackServerContext* context,
                                                     const v1::ComputeFkRequest* request,
                                                     v1::ComputeFkResponse* response) {
  return RunUnary(context, "ComputeFk",
                  [&]() -> Status { return server::ComputeFk(*store_.Snapshot(), *request, response); });
}

grpc::ServerWriteReactor<v1::PoseFrame>* PoseServiceImpl::StreamClip(grpc::CallbackServerContext* context,
                                                                     const v1::StreamClipRequest* request) {
  using Base = grpc::ServerWriteReactor<v1::PoseFrame>;
  return MakeReactor<Base>(context, "StreamClip", [&]() -> Base* {
    auto stream = streams_->Admit(*context, "StreamClip");
    if (!stream.ok()) return new FailedStream<v1::PoseFrame>(stream.status());
    if (Status st = ValidateClipOrMotion(request->clip(), request->has_motion()); !st.ok())
      return new FailedStream<v1::PoseFrame>(st);
    StreamPacing pacing = PacingOf(*request);
    if (Status st = ValidatePacing(pacing, limits_); !st.ok()) return new FailedStream<v1::PoseFrame>(st);
    for (const Status& st : {ValidateEnum(request->interpolation(), v1::Interpolation_descriptor(), "interpolation"),
                             ValidateEnum(request->space(), v1::Space_descriptor(), "space")})
      if (!st.ok()) return new FailedStream<v1::PoseFrame>(st);
    const auto catalog = store_.Snapshot();
    if (request->has_motion())
      return Play(MotionStreamPlan::Make(*catalog, limits_, *request, pacing), pacing, std::move(*stream));
    return Play(ClipStreamPlan::Make(*catalog, limits_, *request, pacing), pacing, std::move(*stream));
  });
}

template <class Plan>
grpc::ServerWriteReactor<typename Plan::Frame>* PoseServiceImpl::Play(StatusOr<Plan> plan, StreamPacing pacing,
                                                                      StreamAdmission::Ticket stream) {
  if (!plan.ok()) return new FailedStream<typename Plan::Frame>(plan.status());
  return new PacedStreamReactor<Plan>(scheduler_, pacing, std::move(*plan), std::move(stream));
}

grpc::ServerBidiReactor<v1::PlaybackCommand, v1::PlaybackFrame>* PoseServiceImpl::PlaybackSession(
    grpc::CallbackServerContext* context) {
  using Base = grpc::ServerBidiReactor<v1::PlaybackCommand, v1::PlaybackFrame>;
  return MakeReactor<Base>(context, "PlaybackSession", [&]() -> Base* {
    auto stream = streams_->Admit(*context, "PlaybackSession");
    if (!stream.ok()) return new FinishedReactor<Base>(stream.status());
    auto session = std::make_unique<server::PlaybackSession>([&store = store_] { return store.Snapshot(); }, limits_);
    return new SessionReactor<server::PlaybackSession>(context, *sessions_, std::move(*stream), std::move(session),
                                                       {.scheduler = &scheduler_});
  });
}

}  // namespace armature::server
