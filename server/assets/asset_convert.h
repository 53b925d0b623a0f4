// Stored assets → their API listings (AssetInfo, SkeletonInfo, ClipInfo,
// MeshInfo), for the List/Get handlers of every slice.
#pragma once

#include "armature/v1/types.pb.h"
#include "server/assets/asset_store.h"

namespace armature::server {

v1::SkeletonInfo SkeletonInfoOf(const StoredAsset& asset, const NamedSkeleton& skeleton);
v1::ClipInfo ClipInfoOf(const StoredAsset& asset, const NamedClip& clip, bool with_joints);
v1::MeshInfo MeshInfoOf(const StoredAsset& asset, const NamedMesh& mesh);
v1::AssetInfo AssetInfoOf(const StoredAsset& asset);

}  // namespace armature::server
