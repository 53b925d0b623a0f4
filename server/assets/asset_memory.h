// How much memory the loaded assets take, for /metrics.
#pragma once

#include <cstddef>

#include "armature/engine/io/asset.h"
#include "server/assets/asset_store.h"
#include "server/rpc/metrics.h"

namespace armature::server {

// Estimated bytes of an asset's parsed data: skeletons (names, parents,
// rest transforms, BVH channels, end sites), clip tracks (key times,
// values, tangents), morph-weight tracks and meshes (positions, normals,
// triangles, UVs, skin and influences, morph targets, the skinning layout;
// materials and their images' stored bytes), each skeleton, mesh, material and image counted once, element storage only
// (no allocator overhead). The uploaded source is not held in memory and is not counted, nor are deformation sessions'
// factorizations (they belong to sessions).
size_t EstimateAssetBytes(const AssetContents& contents);

// EstimateAssetBytes summed over the catalog's assets, but `except` (the one
// an import replaces).
size_t HeldAssetBytes(const Catalog& catalog, const StoredAsset* except = nullptr);

// armature_assets_loaded{kind}, armature_assets_memory_bytes and
// armature_assets_source_bytes of a catalog.
void CollectAssetMetrics(const Catalog& catalog, PrometheusText& out);

}  // namespace armature::server
