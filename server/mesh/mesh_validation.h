// The mesh slice's own request checks (the shared ones are in
// server/rpc/request_validation).
#pragma once

#include <span>
#include <string>

#include "armature/base/status.h"
#include "armature/v1/meshes.pb.h"

namespace armature::server {

// Morph weights: empty, or one finite value per target.
Status ValidateWeights(std::span<const float> weights, size_t targets, const std::string& field);

// A skin request's pose source: a clip or a motion (exactly one), or else pose rotations.
Status ValidateSkinSource(const v1::SkinMeshRequest& request);

// BindMeshRequest.max_influences: 0 (the default) or 1 to 8.
Status ValidateMaxInfluences(int max_influences);

}  // namespace armature::server
