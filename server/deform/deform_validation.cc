#include "server/deform/deform_validation.h"

#include <cmath>

namespace armature::server {

Status ValidateDeformSetup(const v1::DeformSetup& setup) {
  if (setup.soft() && setup.soft_weight() != 0 && !(std::isfinite(setup.soft_weight()) && setup.soft_weight() > 0))
    return Status::InvalidArgument("soft_weight: must be finite and > 0");
  if (setup.arap_iterations() < 0 || setup.arap_iterations() > 1000)
    return Status::InvalidArgument("arap_iterations: must be in [0, 1000] (0 = default 10)");
  return Status::Ok();
}

Status ValidateHandlePositions(std::span<const double> positions, size_t handles, const std::string& field) {
  if (positions.size() != 3 * handles)
    return Status::InvalidArgument(field + ": needs " + std::to_string(3 * handles) +
                                   " values (x, y, z per handle), got " + std::to_string(positions.size()));
  for (size_t i = 0; i < positions.size(); ++i)
    if (!std::isfinite(positions[i]))
      return Status::InvalidArgument(field + ": handle " + std::to_string(i / 3) + " has a non-finite coordinate");
  return Status::Ok();
}

Status ValidateDeformHandles(const google::protobuf::RepeatedPtrField<v1::DeformHandle>& handles) {
  for (int k = 0; k < handles.size(); ++k)
    if (handles[k].position_size() != 3)
      return Status::InvalidArgument("handles[" + std::to_string(k) + "].position: needs 3 values (x, y, z), got " +
                                     std::to_string(handles[k].position_size()));
  return Status::Ok();
}

}  // namespace armature::server
