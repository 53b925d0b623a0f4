#include "server/request_validation.h"

#include <cmath>

namespace armature::server {

Status ValidateFinite(double value, const std::string& field) {
  if (!std::isfinite(value)) return Status::InvalidArgument(field + ": must be a finite number");
  return Status::Ok();
}

Status ValidateTimes(std::span<const double> times, const Limits& limits, const std::string& field) {
  if (times.empty()) return Status::InvalidArgument(field + ": at least one time is required");
  if (times.size() > limits.max_times_per_request)
    return Status::ResourceExhausted(field + ": " + std::to_string(times.size()) + " times exceed the limit of " +
                                     std::to_string(limits.max_times_per_request) + " per request");
  for (size_t i = 0; i < times.size(); ++i) {
    const std::string name = field + "[" + std::to_string(i) + "]";
    if (std::isnan(times[i]) || std::isinf(times[i])) return Status::InvalidArgument(name + ": must be finite");
    if (times[i] < 0) return Status::InvalidArgument(name + ": must not be negative");
  }
  return Status::Ok();
}

StatusOr<std::vector<int>> ResolveJoints(const Skeleton& skeleton,
                                         const google::protobuf::RepeatedPtrField<std::string>& names,
                                         const std::string& field) {
  std::vector<int> joints;
  if (names.empty()) {
    joints.resize(skeleton.size());
    for (size_t i = 0; i < joints.size(); ++i) joints[i] = static_cast<int>(i);
    return joints;
  }
  joints.reserve(names.size());
  for (int i = 0; i < names.size(); ++i) {
    const int j = skeleton.Find(names[i]);
    if (j < 0)
      return Status::NotFound(field + "[" + std::to_string(i) + "]: unknown joint '" + names[i] + "'");
    joints.push_back(j);
  }
  return joints;
}

Status ValidateStreamRequest(v1::StreamClipRequest& r, const Limits& limits) {
  ARMATURE_RETURN_IF_ERROR(ValidateFinite(r.fps(), "fps"));
  ARMATURE_RETURN_IF_ERROR(ValidateFinite(r.speed(), "speed"));
  ARMATURE_RETURN_IF_ERROR(ValidateFinite(r.start_time(), "start_time"));
  ARMATURE_RETURN_IF_ERROR(ValidateFinite(r.duration(), "duration"));
  if (r.fps() == 0) r.set_fps(30);
  if (r.speed() == 0) r.set_speed(1);
  if (r.fps() < 0) return Status::InvalidArgument("fps: must be positive");
  if (r.fps() > limits.max_stream_fps)
    return Status::InvalidArgument("fps: " + std::to_string(r.fps()) + " is above the maximum of " +
                                   std::to_string(limits.max_stream_fps));
  if (r.start_time() < 0) return Status::InvalidArgument("start_time: must not be negative");
  if (r.duration() < 0) return Status::InvalidArgument("duration: must not be negative");
  return Status::Ok();
}

}  // namespace armature::server
