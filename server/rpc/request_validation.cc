#include "server/rpc/request_validation.h"

#include <cctype>
#include <cmath>
#include <cstdio>

#include <google/protobuf/descriptor.h>

#include "armature/base/closest_name.h"

namespace armature::server {

Status ValidateFinite(double value, const std::string& field) {
  if (!std::isfinite(value)) return Status::InvalidArgument(field + ": must be a finite number");
  return Status::Ok();
}

Status ValidateClipTime(double time, const std::string& field) {
  ARMATURE_RETURN_IF_ERROR(ValidateFinite(time, field));
  if (time < 0) return Status::InvalidArgument(field + ": must not be negative");
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
      return Status::NotFound(field + "[" + std::to_string(i) + "]: " + UnknownJoint(names[i], skeleton.names));
    joints.push_back(j);
  }
  return joints;
}

Status ValidatePacing(StreamPacing& p, const Limits& limits) {
  ARMATURE_RETURN_IF_ERROR(ValidateFinite(p.fps, "fps"));
  ARMATURE_RETURN_IF_ERROR(ValidateFinite(p.speed, "speed"));
  ARMATURE_RETURN_IF_ERROR(ValidateFinite(p.start_time, "start_time"));
  ARMATURE_RETURN_IF_ERROR(ValidateFinite(p.duration, "duration"));
  if (p.fps == 0) p.fps = 30;
  if (p.speed == 0) p.speed = 1;
  if (p.fps < 0) return Status::InvalidArgument("fps: must be positive");
  if (p.fps > limits.max_stream_fps)
    return Status::InvalidArgument("fps: " + std::to_string(p.fps) + " is above the maximum of " +
                                   std::to_string(limits.max_stream_fps));
  if (p.start_time < 0) return Status::InvalidArgument("start_time: must not be negative");
  if (p.duration < 0) return Status::InvalidArgument("duration: must not be negative");
  return Status::Ok();
}

Status ValidateClipOrMotion(const std::string& clip, bool has_motion) {
  if (clip.empty() && !has_motion) return Status::InvalidArgument("clip or motion: one is required");
  if (!clip.empty() && has_motion)
    return Status::InvalidArgument("clip and motion: give exactly one (both given; clip '" + clip + "')");
  return Status::Ok();
}

Status ValidateMotion(const v1::Motion& motion, const Limits& limits, const std::string& field) {
  if (motion.layers().empty())
    return Status::InvalidArgument(field + ".layers: the motion is empty (give at least one layer)");
  if (motion.layers_size() > limits.max_motion_layers)
    return Status::InvalidArgument(field + ".layers: " + std::to_string(motion.layers_size()) + " layers, at most " +
                                   std::to_string(limits.max_motion_layers));
  ARMATURE_RETURN_IF_ERROR(ValidateEnum(motion.sync(), v1::Motion::Sync_descriptor(), field + ".sync"));
  ARMATURE_RETURN_IF_ERROR(
      ValidateEnum(motion.root_motion(), v1::Motion::RootMotion_descriptor(), field + ".rootMotion"));
  for (int i = 0; i < motion.layers_size(); ++i) {
    const v1::MotionLayer& l = motion.layers(i);
    const std::string where =
        field + ".layers[" + std::to_string(i) + "]" + (l.clip().empty() ? "" : " (clip '" + l.clip() + "')");
    ARMATURE_RETURN_IF_ERROR(ValidateRequired(l.clip(), where + ".clip"));
    if (l.has_weight() && !(l.weight() >= 0 && l.weight() <= 1))
      return Status::InvalidArgument(where + ": weight " + std::to_string(l.weight()) + " is outside [0, 1]");
    if (l.has_speed()) ARMATURE_RETURN_IF_ERROR(ValidateFinite(l.speed(), where + ".speed"));
    ARMATURE_RETURN_IF_ERROR(ValidateFinite(l.time_offset(), where + ".timeOffset"));
    ARMATURE_RETURN_IF_ERROR(ValidateClipTime(l.reference_time(), where + ".referenceTime"));
    ARMATURE_RETURN_IF_ERROR(ValidateEnum(l.mode(), v1::MotionLayer::Mode_descriptor(), where + ".mode"));
    ARMATURE_RETURN_IF_ERROR(ValidateEnum(l.wrap(), v1::WrapMode_descriptor(), where + ".wrap"));
    if (l.mask_size() > limits.max_motion_mask_joints)
      return Status::InvalidArgument(where + ".mask: " + std::to_string(l.mask_size()) + " joints, at most " +
                                     std::to_string(limits.max_motion_mask_joints));
    if (!l.mask_weights().empty() && l.mask_weights_size() != l.mask_size())
      return Status::InvalidArgument(where + ".maskWeights: " + std::to_string(l.mask_weights_size()) +
                                     " weights for " + std::to_string(l.mask_size()) +
                                     " mask joints (give one per joint, or none)");
    for (int k = 0; k < l.mask_weights_size(); ++k)
      if (!(l.mask_weights(k) >= 0 && l.mask_weights(k) <= 1))
        return Status::InvalidArgument(where + ".maskWeights[" + std::to_string(k) +
                                       "]: " + std::to_string(l.mask_weights(k)) + " is outside [0, 1]");
  }
  return Status::Ok();
}

Status ValidateReplySize(double bytes, const Limits& limits, const std::string& rpc, const std::string& how) {
  if (bytes <= static_cast<double>(limits.max_message_bytes)) return Status::Ok();
  char size[64];
  std::snprintf(size, sizeof size, "%.1f MiB", bytes / (1 << 20));
  char limit[64];
  std::snprintf(limit, sizeof limit, "%.1f MiB", static_cast<double>(limits.max_message_bytes) / (1 << 20));
  return Status::ResourceExhausted(rpc + ": the answer would take at least " + size + " (" + how +
                                   "), over the message limit of " + limit + " (--max-message-mb); ask for less");
}

Status ValidateEnum(int value, const google::protobuf::EnumDescriptor* type, const std::string& field) {
  if (type->FindValueByNumber(value) != nullptr) return Status::Ok();
  std::string allowed;
  for (int i = 0; i < type->value_count(); ++i)
    allowed += (i ? ", " : "") + type->value(i)->name() + " (" + std::to_string(type->value(i)->number()) + ")";
  return Status::InvalidArgument(field + ": unknown value " + std::to_string(value) + "; allowed: " + allowed);
}

Status ValidateRequired(const std::string& value, const std::string& field) {
  if (value.empty()) return Status::InvalidArgument(field + ": required");
  return Status::Ok();
}

StatusOr<std::array<Axis, 3>> ParseEulerOrder(const std::string& order, const std::string& field) {
  std::array<Axis, 3> axes = {Axis::kX, Axis::kY, Axis::kZ};
  if (order.empty()) return axes;
  auto bad = [&] {
    return Status::InvalidArgument(
        field + ": expected X, Y and Z once each, in the order they apply, such as \"ZXY\", got \"" + order + "\"");
  };
  if (order.size() != 3) return bad();
  bool seen[3] = {false, false, false};  // an axis twice ("XXX", "XYX") is no Tait-Bryan order
  for (int k = 0; k < 3; ++k) {
    const int c = std::toupper(static_cast<unsigned char>(order[k]));
    if (c < 'X' || c > 'Z' || seen[c - 'X']) return bad();
    seen[c - 'X'] = true;
    axes[k] = static_cast<Axis>(c - 'X');
  }
  return axes;
}

}  // namespace armature::server
