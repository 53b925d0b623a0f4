// CreateClip's work: keys per joint validated, built into a clip on the
// skeleton and stored as a new asset (derived_clip).
#pragma once

#include "armature/base/status.h"
#include "armature/v1/clip_keys.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"

namespace armature::server {

Status CreateClip(AssetStore& store, const Limits& limits, const v1::CreateClipRequest& request,
                  v1::CreateClipResponse* response);

}  // namespace armature::server
