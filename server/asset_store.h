// The asset store: every imported file, parsed, named and persisted.
//
// Reads take an immutable Catalog snapshot (shared_ptr, lock-free for the
// caller), so a delete or replace never breaks an in-flight call: the call
// keeps the parts it already holds. Writes are serialized, persisted first
// (source file + manifest, each written to a temporary file, fsynced and
// renamed) and published second, so a crash mid-import leaves no half asset.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>

#include "armature/engine/asset.h"
#include "armature/engine/status.h"

namespace armature::server {

// What the manifest records of one imported file.
struct AssetRecord {
  std::string name;
  AssetFormat format = AssetFormat::kBvh;
  std::string filename;  // as uploaded
  std::string file;      // stored source, relative to the data dir
  int64_t size_bytes = 0;
  std::string imported_at;  // RFC 3339, UTC
  std::map<std::string, std::string> resources;  // uri → stored file, relative to the data dir
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
  // The asset named `name`, or the one owning a clip, skeleton or mesh of that name.
  StatusOr<std::shared_ptr<const StoredAsset>> FindOwner(std::string_view name) const;
};

struct ImportRequest {
  std::string name;      // empty: the filename's stem
  std::string filename;
  std::string format;    // empty: detect
  bool replace = false;
  std::string bytes;
  ResourceMap resources;  // further files by uri (a .gltf's .bin buffers)
};

class AssetStore {
 public:
  // Opens (creating if needed) a data dir and loads every asset in its
  // manifest. Assets that no longer parse are logged and skipped, never deleted.
  static StatusOr<std::unique_ptr<AssetStore>> Open(const std::filesystem::path& data_dir);

  std::shared_ptr<const Catalog> Snapshot() const;

  // Parses, persists, then publishes. INVALID_ARGUMENT for bad files or
  // names, ALREADY_EXISTS for a taken name (unless replace).
  StatusOr<std::shared_ptr<const StoredAsset>> Import(ImportRequest request);
  // Removes the asset owning `name` from the manifest, then its file.
  StatusOr<std::shared_ptr<const StoredAsset>> Delete(std::string_view name);

  // True when the data dir had no manifest when opened (a first start).
  bool fresh() const { return fresh_; }
  const std::filesystem::path& data_dir() const { return dir_; }

 private:
  explicit AssetStore(std::filesystem::path dir) : dir_(std::move(dir)) {}
  Status Load();
  Status WriteManifest(const Catalog& catalog) const;
  void Publish(std::shared_ptr<const Catalog> catalog);

  std::filesystem::path dir_;
  bool fresh_ = false;
  std::mutex write_mu_;  // one writer at a time
  mutable std::mutex snapshot_mu_;
  std::shared_ptr<const Catalog> catalog_;
};

// Asset names become file names: letters, digits, '.', '_' and '-', not
// starting with '.', at most 128 characters.
Status ValidateAssetName(std::string_view name);

// Builds a Catalog's part indexes from its assets.
StatusOr<std::shared_ptr<Catalog>> BuildCatalog(std::map<std::string, std::shared_ptr<const StoredAsset>> assets);

}  // namespace armature::server
