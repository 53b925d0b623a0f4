// PoseService's unary work without gRPC (benchmarks, tests): clip and
// motion evaluation, forward kinematics, and what an evaluation costs.
#pragma once

#include "armature/base/status.h"
#include "armature/v1/poses.pb.h"
#include "server/assets/catalog.h"
#include "server/rpc/limits.h"
#include "server/rpc/reply_size.h"
#include "server/rpc/work/call_progress.h"
#include "server/rpc/work/work_budget.h"

namespace armature::server {

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
