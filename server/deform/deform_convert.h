// DeformService's messages ↔ the deformer's inputs: the unary request's
// constraint fields as a session's setup, its handles as indices and packed
// positions.
#pragma once

#include <cstdint>
#include <vector>

#include "armature/base/status.h"
#include "armature/v1/deform.pb.h"

namespace armature::server {

// The unary request's constraint fields as a setup, and its handles split
// into indices and packed positions (each position must have 3 values).
v1::DeformSetup SetupOf(const v1::DeformRequest& request);
Status SplitHandles(const v1::DeformRequest& request, std::vector<uint32_t>* indices, std::vector<double>* positions);

}  // namespace armature::server
