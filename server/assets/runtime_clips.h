// Clips' runtime form in the server: each clip compressed once (CompressClip)
// under its import's precision when its asset is parsed (import, or load from
// the data dir). The server samples nothing else (ClipSamplingJob).
#pragma once

#include "armature/base/status.h"
#include "armature/engine/anim/compression/error_bound.h"
#include "armature/engine/io/asset.h"

namespace armature::server {

// Sets each clip's `runtime` and drops the file form (`clip`) it replaces
// (an exact runtime form keeps it: its keys). A clip that cannot meet
// `precision` is kept exact: its warning is added to contents.warnings (and
// logged).
Status CompressClips(AssetContents& contents, const ClipPrecision& precision);

}  // namespace armature::server
