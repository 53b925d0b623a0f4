// RetargetClip's work: a source clip moved onto a target skeleton and stored
// as a new asset (derived_clip).
#pragma once

#include "armature/base/status.h"
#include "armature/v1/retarget.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"

namespace armature::server {

Status RetargetClip(AssetStore& store, const Limits& limits, const v1::RetargetClipRequest& request,
                    v1::RetargetClipResponse* response);

}  // namespace armature::server
