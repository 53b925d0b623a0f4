#include "server/crowd/crowd_watch.h"

#include <algorithm>
#include <string>
#include <utility>

namespace armature::server {

StatusOr<CrowdWatchPlan> CrowdWatchPlan::Make(CatalogSource catalog, const Limits& limits,
                                              std::shared_ptr<CrowdTotals> totals,
                                              const v1::WatchCrowdRequest& request) {
  // Checked before any is added, so a huge request costs nothing.
  if (request.characters_size() > limits.max_crowd_characters)
    return Status::ResourceExhausted("characters: " + std::to_string(request.characters_size()) +
                                     " is over --max-crowd-characters (" + std::to_string(limits.max_crowd_characters) +
                                     ")");
  auto session = std::make_unique<CrowdSession>(std::move(catalog), limits, std::move(totals));
  v1::CrowdCommand command;
  *command.mutable_start() = request.start();
  ARMATURE_RETURN_IF_ERROR(session->Start(CallStop{}, command));
  for (const v1::CrowdCharacter& character : request.characters()) {
    *command.mutable_add() = character;
    session->Queue(command);
  }
  ARMATURE_RETURN_IF_ERROR(session->ApplyQueued());
  ARMATURE_RETURN_IF_ERROR(session->first_refusal());
  StreamPacing pacing;
  pacing.fps = session->fps();
  pacing.loop = true;
  pacing.duration = request.start().duration();
  if (request.max_ticks() > 0) {
    const double ticks = static_cast<double>(request.max_ticks()) / pacing.fps;
    pacing.duration = pacing.duration > 0 ? std::min(pacing.duration, ticks) : ticks;
  }
  return CrowdWatchPlan(std::move(session), pacing);
}

Status CrowdWatchPlan::Fill(uint64_t /*index*/, double /*time*/, WrapMode /*wrap*/, Frame& frame) {
  ARMATURE_ASSIGN_OR_RETURN(bool more, session_->NextFrame(/*closed=*/false, &frame));
  // The pacing ends the stream at the session's duration, so the session never runs out first.
  if (!more) return Status(StatusCode::kInternal, "crowd watch: the session ended before its pacing");
  return Status::Ok();
}

}  // namespace armature::server
