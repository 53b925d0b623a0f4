#include "server/ik/ik_session_reactor.h"

#include <spdlog/spdlog.h>

#include "server/rpc/call_guard.h"
#include "server/rpc/grpc_status.h"
#include "server/ik/ik_solve.h"

namespace armature::server {

namespace {
// Names the field as the client sees it: "start.effectors[1].joint",
// "message 7: targets[0].target_position". Interruptions name no field.
Status InContext(const Status& status, uint64_t message) {
  const StatusCode code = status.code();
  if (status.ok() || code == StatusCode::kDeadlineExceeded || code == StatusCode::kCancelled) return status;
  return status.WithContext(message == 0 ? "start." : "message " + std::to_string(message) + ": ");
}
}  // namespace

IkSessionReactor::IkSessionReactor(grpc::CallbackServerContext* context, AssetStore& store, const Limits& limits,
                                   SessionAdmission& sessions, StreamAdmission::Ticket stream)
    : context_(context), store_(store), limits_(limits), stream_(std::move(stream)) {
  auto ticket = sessions.Admit(*context, SessionKind::kIk);
  if (!ticket.ok()) {
    End(ToGrpcStatus(ticket.status()));
    return;
  }
  ticket_ = std::move(*ticket);
  StartRead(&request_);
}

void IkSessionReactor::OnReadDone(bool ok) {
  GuardCallback(context_, "IkSession", [&] { ReadDone(ok); }, [this](grpc::Status st) { End(std::move(st)); });
}

void IkSessionReactor::OnWriteDone(bool ok) {
  GuardCallback(context_, "IkSession", [&] { WriteDone(ok); }, [this](grpc::Status st) { End(std::move(st)); });
}

void IkSessionReactor::ReadDone(bool ok) {
  // Not ok: the client closed its side (or went away): the session is over.
  if (!ok) return End(grpc::Status::OK);
  if (Status status = Answer(); !status.ok()) return End(ToGrpcStatus(status));
  ++index_;
  StartWrite(&response_);
}

void IkSessionReactor::WriteDone(bool ok) {
  if (!ok) return End(grpc::Status(grpc::StatusCode::CANCELLED, "the client went away"));
  request_.Clear();
  StartRead(&request_);
}

void IkSessionReactor::OnDone() {
  spdlog::debug("IK session on '{}' done after {} messages",
                call_.skeleton.part ? call_.skeleton.part->name : std::string("?"), index_);
  delete this;  // the ticket, if still held, goes with it
}

void IkSessionReactor::End(grpc::Status status) {
  // Free the place before the client hears the session is over, so it can
  // open another at once.
  ticket_.Release();
  Finish(std::move(status));
}

Status IkSessionReactor::Answer() {
  ARMATURE_RETURN_IF_ERROR(index_ == 0 ? Start() : Update());
  return InContext(RunIk(call_, workspace_, result_, pose_, &response_), index_);
}

Status IkSessionReactor::Start() {
  if (!request_.has_start())
    return Status::InvalidArgument("start: required in the first message (skeleton, start pose, effectors, solver)");
  if (!request_.targets().empty())
    return Status::InvalidArgument("targets: not in the first message; its start.effectors carry the first targets");
  ARMATURE_RETURN_IF_ERROR(InContext(IkCallFromProto(*store_.Snapshot(), limits_, request_.start(), call_), 0));
  call_.request.deadline = SteadyDeadline(*context_);
  call_.request.should_stop = [context = context_] { return context->IsCancelled(); };
  return Status::Ok();
}

Status IkSessionReactor::Update() {
  if (request_.has_start())
    return InContext(Status::InvalidArgument("start: only in the first message"), index_);
  ARMATURE_RETURN_IF_ERROR(InContext(ApplyTargetUpdates(request_.targets(), call_.request), index_));
  call_.start = result_.pose;  // warm start from the last answer
  call_.request.start_pose = call_.start;
  return Status::Ok();
}

}  // namespace armature::server
