// One IK session's logic, without gRPC: the first message (`start`) sets up
// the solve and is answered; each later one moves targets and is answered
// with a solve warm-started from the previous answer. Run by
// SessionReactor<IkSession> (server/rpc/streams/session_reactor.h).
#pragma once

#include <cstdint>

#include "armature/engine/kinematics/ik_workspace.h"
#include "armature/v1/ik.pb.h"
#include "server/assets/catalog.h"
#include "server/ik/ik_convert.h"
#include "server/rpc/limits.h"
#include "server/rpc/call_stop.h"
#include "server/rpc/streams/session_kind.h"

namespace armature::server {

class IkSession {
 public:
  using Request = v1::IkSessionRequest;
  using Response = v1::SolveIkResponse;
  static constexpr SessionKind kKind = SessionKind::kIk;
  static constexpr const char* kName = "IkSession";

  IkSession(CatalogSource catalog, const Limits& limits) : catalog_(std::move(catalog)), limits_(limits) {}
  ~IkSession();

  // Errors name the field as the client sees it ("start.effectors[1].joint",
  // "message 7: targets[0].target_position"); interruptions (the call's
  // deadline, cancellation) name none.
  Status Start(const CallStop& call, const Request& first, Response* response);
  Status Answer(const Request& next, Response* response);

 private:
  Status Solve(Response* response);

  CatalogSource catalog_;
  const Limits& limits_;
  uint64_t messages_ = 0;  // answered
  IkCall call_;
  IkWorkspace workspace_;
  IkResult result_;
  PoseWorkspace pose_;
};

}  // namespace armature::server
