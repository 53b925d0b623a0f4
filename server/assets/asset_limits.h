// Import-time limits on what one file may contain, checked after parsing
// and before anything is stored.
#pragma once

#include "armature/engine/io/asset.h"
#include "armature/engine/io/import_limits.h"
#include "armature/base/status.h"
#include "server/rpc/limits.h"

namespace armature::server {

// RESOURCE_EXHAUSTED naming the part, its size, the limit and its flag:
// clips over --max-clip-frames, meshes over --max-mesh-vertices.
Status CheckAssetLimits(const AssetContents& contents, const Limits& limits);

// The engine's import caps with the flag-backed ones taken from `limits`, so
// oversized files are refused while parsing, before they allocate.
ImportLimits ImportLimitsOf(const Limits& limits);

// ImportLimitsOf with the decoded-size cap lowered to the room left under
// --max-assets-mb when the server holds `held_bytes` of assets.
ImportLimits ImportLimitsWithRoom(const Limits& limits, size_t held_bytes);

// RESOURCE_EXHAUSTED naming --max-assets-mb, the sizes and the limit when
// `adding_bytes` more would take the assets' memory past it.
Status CheckAssetsTotal(size_t adding_bytes, size_t held_bytes, const Limits& limits);

// The caps for reading back what is already stored: never below the engine's
// defaults, so lowering a flag does not drop assets imported before, and
// raised with the flags, so what a raised flag let in loads again.
ImportLimits LoadLimitsOf(const Limits& limits);

// `parsed` with the flag named after an engine cap that has one
// ("... max_clip_frames = 10 (--max-clip-frames)").
StatusOr<AssetContents> WithLimitFlags(StatusOr<AssetContents> parsed);

}  // namespace armature::server
