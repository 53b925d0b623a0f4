// A clip the server made (retargeted, authored from keys), stored as an asset
// exactly like an import: written as glTF binary (the skeleton as nodes, the
// clip as one animation) and handed to AssetStore::Import. So it is persisted,
// reloaded at restart, listed, evaluable, exportable and deleted on its own,
// and the clip callers get back is the one parsed from the stored bytes: what
// they see now is what they see after a restart. The clip belongs to the
// skeleton it was made for (AssetRecord::animates): named as the asset (the
// name the caller gave), listed as that skeleton's, played, blended, skinned
// and exported with its clips and meshes.
#pragma once

#include <memory>
#include <string>

#include "armature/base/status.h"
#include "armature/engine/anim/clip.h"
#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"

namespace armature::server {

struct DerivedClipOptions {
  std::string asset_name;  // validated like any asset name; the clip's name too
  // The skeleton it animates (the clip's own skeleton is a copy of it); empty:
  // the asset keeps the copy as a skeleton of its own, and the clip is
  // "<asset_name>.<asset_name>" (CreateClip's merge into such an older clip).
  std::string skeleton;
  bool replace = false;  // replace an asset of that name instead of ALREADY_EXISTS
  // Set: replace exactly this stored asset (ABORTED if another took its place meanwhile).
  std::shared_ptr<const StoredAsset> replace_only;
  std::string precision;  // ImportRequest::precision: empty, the server's default
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
