// A clip the server made (retargeted, authored from keys), stored as an asset
// exactly like an import: written as glTF binary (the skeleton as nodes, the
// clip as one animation) and handed to AssetStore::Import. So it is persisted,
// reloaded at restart, listed, evaluable, exportable and deleted on its own,
// and the clip callers get back is the one parsed from the stored bytes: what
// they see now is what they see after a restart.
#pragma once

#include <memory>
#include <string>

#include "armature/base/status.h"
#include "armature/engine/anim/clip.h"
#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"

namespace armature::server {

struct DerivedClipOptions {
  std::string asset_name;      // validated like any asset name
  std::string animation_name;  // the clip is then "<asset_name>.<animation_name>"
  bool replace = false;        // replace an asset of that name instead of ALREADY_EXISTS
  // Set: replace exactly this stored asset (ABORTED if another took its place meanwhile).
  std::shared_ptr<const StoredAsset> replace_only;
};

struct DerivedClip {
  std::shared_ptr<const StoredAsset> asset;
  const NamedClip* clip = nullptr;  // points into asset->contents
};

// Refuses a file over --max-upload-mb (RESOURCE_EXHAUSTED naming the flag)
// before writing it.
StatusOr<DerivedClip> StoreDerivedClip(AssetStore& store, const Clip& clip, const DerivedClipOptions& options,
                                       const Limits& limits);

}  // namespace armature::server
