#include "server/deform/deform_session.h"

#include <string>
#include <vector>

#include "server/rpc/convert/pose_convert.h"

namespace armature::server {

Status DeformSession::Start(const CallStop& /*call*/, const Request& first, Response* response) {
  if (!first.has_start())
    return Status::InvalidArgument("start: the first message of a session must be `start` (mesh and constraints)");
  const auto& start = first.start();
  std::vector<uint32_t> handles(start.handle_indices().begin(), start.handle_indices().end());
  ARMATURE_ASSIGN_OR_RETURN(MeshDeformer deformer,
                            MeshDeformer::Create(*catalog_(), limits_, start.setup(), std::move(handles)));
  deformer_.emplace(std::move(deformer));
  // The setup's answer: the handles at rest, i.e. the rest shape.
  ARMATURE_RETURN_IF_ERROR(deformer_->Solve(deformer_->RestHandlePositions(), "start", response));
  response->set_index(0);
  return Status::Ok();
}

Status DeformSession::Answer(const Request& next, Response* response) {
  if (!next.has_move())
    return Status::InvalidArgument("move: messages after the first must be `move` (handle positions)");
  ++moves_;
  ARMATURE_RETURN_IF_ERROR(
      deformer_->Solve(AsSpan(next.move().positions()), "move[" + std::to_string(moves_) + "].positions", response));
  response->set_index(moves_);
  return Status::Ok();
}

}  // namespace armature::server
