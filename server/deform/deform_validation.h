// The deform slice's own request checks (the shared ones are in
// server/rpc/request_validation).
#pragma once

#include <span>
#include <string>

#include "armature/base/status.h"
#include "armature/v1/deform.pb.h"

namespace armature::server {

// A deformation setup's own numbers: soft_weight (soft only; 0 = default)
// finite and > 0, arap_iterations in [0, 1000].
Status ValidateDeformSetup(const v1::DeformSetup& setup);

// x, y, z for each of `handles` handles, every value finite; errors name `field`.
Status ValidateHandlePositions(std::span<const double> positions, size_t handles, const std::string& field);

// A unary Deform's handles: each position has 3 values (x, y, z).
Status ValidateDeformHandles(const google::protobuf::RepeatedPtrField<v1::DeformHandle>& handles);

}  // namespace armature::server
