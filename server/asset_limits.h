// Import-time limits on what one file may contain, checked after parsing
// and before anything is stored.
#pragma once

#include "armature/engine/asset.h"
#include "armature/engine/status.h"
#include "server/limits.h"

namespace armature::server {

// RESOURCE_EXHAUSTED naming the part, its size, the limit and its flag:
// clips over --max-clip-frames, meshes over --max-mesh-vertices.
Status CheckAssetLimits(const AssetContents& contents, const Limits& limits);

}  // namespace armature::server
