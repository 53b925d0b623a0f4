#include "server/rpc/work/work_budget.h"

#include <cmath>
#include <cstdio>

namespace armature::server {

Status ValidateRequestWork(const RequestWork& work, const Limits& limits, const std::string& rpc) {
  if (work.total() <= limits.max_request_work) return Status::Ok();
  return Status::ResourceExhausted(rpc + ": " + std::to_string(work.layers) + " layers x " +
                                   std::to_string(work.times) + " times x " + std::to_string(work.joints) +
                                   " joints = " + std::to_string(work.total()) + " joint samples, over the budget of " +
                                   std::to_string(limits.max_request_work) +
                                   " per request (--max-request-work); ask for fewer times or layers");
}

Status ValidateStreamWork(int64_t layers, int64_t joints, double fps, const Limits& limits, const std::string& field) {
  const double work = static_cast<double>(layers) * static_cast<double>(joints) * fps;
  if (work <= static_cast<double>(limits.max_stream_work)) return Status::Ok();
  char rate[32];
  std::snprintf(rate, sizeof rate, "%g", fps);
  return Status::ResourceExhausted(
      field + ": " + std::to_string(layers) + " layers x " + std::to_string(joints) + " joints x " + rate + " fps = " +
      std::to_string(static_cast<int64_t>(std::llround(work))) + " joint samples a second, over the budget of " +
      std::to_string(limits.max_stream_work) + " (--max-stream-work); play fewer layers or at a lower fps");
}

}  // namespace armature::server
