// The catalog: an immutable snapshot of every loaded asset and indexes of
// their named parts (clips, skeletons, meshes). Handlers read one snapshot
// per call; the AssetStore publishes a new one after each write.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "armature/base/status.h"
#include "armature/engine/io/asset.h"

namespace armature::server {

// What the manifest records of one imported file.
struct AssetRecord {
  std::string name;
  AssetFormat format = AssetFormat::kBvh;
  std::string filename;  // as uploaded
  std::string file;      // stored source, relative to the data dir
  int64_t size_bytes = 0;
  std::string imported_at;                       // RFC 3339, UTC
  std::map<std::string, std::string> resources;  // uri → stored file, relative to the data dir
  // Set: the asset is one clip the server made for this skeleton (retargeted,
  // created from keys): its clip is named after the asset and animates the
  // skeleton of that name, joint for joint; the file's copy of the skeleton
  // is not listed as a skeleton of its own (AdoptDerivedClip).
  std::string animates;
  // "<UTC time>-<writer id>", sorting in import order (bucket_layout.h's
  // NewVersion); empty in manifests written before versions existed.
  std::string version;
  // The clips' precision, as ClipPrecisionText ("exact", or centimetres).
  std::string precision;
};

struct StoredAsset {
  AssetRecord record;
  AssetContents contents;
};

// A named part and the asset that owns it.
template <class Part>
struct PartRef {
  std::shared_ptr<const StoredAsset> asset;
  const Part* part = nullptr;  // points into asset->contents
};

// An immutable view of everything loaded.
struct Catalog {
  std::map<std::string, std::shared_ptr<const StoredAsset>> assets;
  std::map<std::string, PartRef<NamedClip>> clips;
  std::map<std::string, PartRef<NamedSkeleton>> skeletons;
  std::map<std::string, PartRef<NamedMesh>> meshes;

  StatusOr<PartRef<NamedClip>> FindClip(std::string_view name) const;
  StatusOr<PartRef<NamedSkeleton>> FindSkeleton(std::string_view name) const;
  StatusOr<PartRef<NamedMesh>> FindMesh(std::string_view name) const;
  // A character: the meshes skinned to the skeleton named `skeleton`, in name order.
  std::vector<const NamedMesh*> MeshesOf(std::string_view skeleton) const;
  // The asset named `name`, or the one owning a clip, skeleton or mesh of that name.
  StatusOr<std::shared_ptr<const StoredAsset>> FindOwner(std::string_view name) const;
};

// Where a long-lived call (a session) takes the catalog's latest snapshot
// each time it looks a name up: AssetStore::Snapshot, or a fixed one in tests.
using CatalogSource = std::function<std::shared_ptr<const Catalog>()>;

// A derived clip's parsed file made the clip of skeleton `record.animates`:
// its one clip renamed `record.name`, its copy of the skeleton dropped from
// the parts. INVALID_ARGUMENT when the file holds other than one clip.
Status AdoptDerivedClip(const AssetRecord& record, AssetContents& contents);

// Builds a Catalog's part indexes from its assets.
StatusOr<std::shared_ptr<Catalog>> BuildCatalog(std::map<std::string, std::shared_ptr<const StoredAsset>> assets);

}  // namespace armature::server
