// Built-in demo assets, seeded into an empty data dir so a first `make run`
// serves real motion with nothing to download: the clip demo_walk (a BVH)
// and the skinned, walking character demo_character (a glb).
#pragma once

#include "armature/base/status.h"
#include "server/assets/asset_store.h"

namespace armature::server {

Status SeedDemoAssets(AssetStore& store);

}  // namespace armature::server
