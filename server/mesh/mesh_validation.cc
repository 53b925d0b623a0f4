#include "server/mesh/mesh_validation.h"

#include <cmath>

#include "server/rpc/request_validation.h"

namespace armature::server {

Status ValidateWeights(std::span<const float> weights, size_t targets, const std::string& field) {
  if (weights.empty()) return Status::Ok();
  if (weights.size() != targets)
    return Status::InvalidArgument(field + ": " + std::to_string(weights.size()) + " values for " +
                                   std::to_string(targets) + " morph targets (give one per target, or none)");
  for (size_t i = 0; i < weights.size(); ++i)
    if (!std::isfinite(weights[i]))
      return Status::InvalidArgument(field + "[" + std::to_string(i) + "]: must be a finite number");
  return Status::Ok();
}

Status ValidateSkinSource(const v1::SkinMeshRequest& request) {
  if (request.clip().empty() && !request.has_motion() && request.pose().rotations().empty())
    return Status::InvalidArgument(
        "clip, motion or pose.rotations: one is required (pose: 4 rotation values per joint)");
  // A pose beside a clip is ignored (the clip poses the mesh), as it always was.
  if (request.has_motion() && !request.pose().rotations().empty())
    return Status::InvalidArgument("motion and pose.rotations: give exactly one (both given)");
  return request.has_motion() ? ValidateClipOrMotion(request.clip(), true) : Status::Ok();
}

Status ValidateMaxInfluences(int max_influences) {
  if (max_influences < 0 || max_influences > 8)
    return Status::InvalidArgument("max_influences: must be between 1 and 8");
  return Status::Ok();
}

}  // namespace armature::server
