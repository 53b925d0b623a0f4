// IkService's work without gRPC: the unary SolveIk, and one solve from a
// converted call to its answer (RunIk), shared with the IK session.
#pragma once

#include "armature/base/status.h"
#include "armature/engine/kinematics/ik_workspace.h"
#include "armature/v1/ik.pb.h"
#include "server/assets/catalog.h"
#include "server/ik/ik_convert.h"
#include "server/rpc/call_stop.h"
#include "server/rpc/convert/pose_convert.h"
#include "server/rpc/limits.h"

namespace armature::server {

// Solves `call` (its request carrying any deadline and cancel check) and
// writes the answer. INVALID_ARGUMENT naming the API field for bad input;
// DEADLINE_EXCEEDED or CANCELLED when interrupted; an unreachable target is OK.
Status RunIk(const IkCall& call, IkWorkspace& workspace, IkResult& result, PoseWorkspace& pose,
             v1::SolveIkResponse* response);

// The unary SolveIk: the request converted, solved on this thread's
// workspace, answered. The solver stops at `stop`'s deadline or
// cancellation, so no CPU is spent on an answer nobody waits for.
Status SolveIk(const Catalog& catalog, const Limits& limits, const v1::SolveIkRequest& request,
               v1::SolveIkResponse* response, const CallStop& stop = {});

}  // namespace armature::server
