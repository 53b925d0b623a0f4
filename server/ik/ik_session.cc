#include "server/ik/ik_session.h"

#include <string>

#include <spdlog/spdlog.h>

#include "server/ik/ik_handlers.h"

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

IkSession::~IkSession() {
  spdlog::debug("IK session on '{}' done after {} messages",
                call_.skeleton.part ? call_.skeleton.part->name : std::string("?"), messages_);
}

Status IkSession::Start(const CallStop& call, const Request& first, Response* response) {
  if (!first.has_start())
    return Status::InvalidArgument("start: required in the first message (skeleton, start pose, effectors, solver)");
  if (!first.targets().empty())
    return Status::InvalidArgument("targets: not in the first message; its start.effectors carry the first targets");
  ARMATURE_RETURN_IF_ERROR(InContext(IkCallFromProto(*catalog_(), limits_, first.start(), call_), 0));
  call_.request.deadline = call.deadline;
  call_.request.should_stop = call.cancelled;
  return Solve(response);
}

Status IkSession::Answer(const Request& next, Response* response) {
  if (next.has_start()) return InContext(Status::InvalidArgument("start: only in the first message"), messages_);
  ARMATURE_RETURN_IF_ERROR(InContext(ApplyTargetUpdates(next.targets(), call_.request), messages_));
  call_.start = result_.pose;  // warm start from the last answer
  call_.request.start_pose = call_.start;
  return Solve(response);
}

Status IkSession::Solve(Response* response) {
  ARMATURE_RETURN_IF_ERROR(InContext(RunIk(call_, workspace_, result_, pose_, response), messages_));
  ++messages_;
  return Status::Ok();
}

}  // namespace armature::server
