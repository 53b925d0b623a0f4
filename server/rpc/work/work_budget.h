// The work a request asks for, counted before any is done and checked
// against a stated budget: the one place every heavy handler asks. Work is
// counted in joint samples (one layer of one joint at one time); going over
// is RESOURCE_EXHAUSTED naming the budget's flag and the request's cost.
#pragma once

#include <cstdint>
#include <string>

#include "armature/base/status.h"
#include "server/rpc/limits.h"

namespace armature::server {

// A unary evaluation's cost: layers × times × joints (a clip is one layer).
struct RequestWork {
  int64_t layers = 1;
  int64_t times = 0;
  int64_t joints = 0;
  int64_t total() const { return layers * times * joints; }
};

// `work` against --max-request-work; `rpc` names the call in the error.
Status ValidateRequestWork(const RequestWork& work, const Limits& limits, const std::string& rpc);

// A stream's or session's cost a second: layers × joints × fps against
// --max-stream-work; `field` names what asked for it ("play.motion").
Status ValidateStreamWork(int64_t layers, int64_t joints, double fps, const Limits& limits, const std::string& field);

}  // namespace armature::server
