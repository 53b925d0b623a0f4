// Deleting by a part's name (DELETE /v1/clips/fox.Walk) must not silently drop the rest of the
// asset that holds it: a file is stored, and deleted, whole.
#pragma once

#include <string_view>

#include "armature/base/status.h"
#include "server/assets/catalog.h"

namespace armature::server {

// OK when deleting `name` removes nothing else: `name` is the asset's own name, or the asset holds
// only that part. Otherwise FAILED_PRECONDITION naming the asset and what else it holds: "clip
// 'fox.Walk' belongs to asset 'fox', which also holds 2 clips, 1 mesh and 1 skeleton; delete the
// asset 'fox' to remove them all".
Status CheckDeletionTakesOnly(const StoredAsset& owner, std::string_view name);

}  // namespace armature::server
