// The asset store: every imported file, parsed, named and persisted.
//
// Reads take an immutable Catalog snapshot (shared_ptr, lock-free for the
// caller), so a delete or replace never breaks an in-flight call: the call
// keeps the parts it already holds. Writes are serialized, persisted first
// (source file + manifest, each written to a temporary file, fsynced and
// renamed) and published second, so a crash mid-import leaves no half asset.
//
// Several servers may share one data dir (replicas on a ReadWriteMany
// volume). Each write is a read-modify-write of the manifest under an
// exclusive DataDirLock, re-reading the manifest first, so concurrent
// writers never lose each other's entries. Each server watches the manifest
// and reloads it when another one changed it: unchanged entries keep their
// parsed assets, only new ones are parsed. Files are written before the
// manifest names them, so no server ever sees a half-written asset.
//
// With a bucket (--store s3://…) the bucket is the truth and the data dir a
// local cache of it, its manifest the cache's index: writes go to the
// bucket first (bucket/bucket_layout.h: no lock between replicas), and every
// watch_interval each server lists the bucket and loads the latest version
// of each name. A version that cannot be read or parsed is logged, counted
// and skipped, the version serving before staying in place.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#include "armature/base/status.h"
#include "armature/engine/anim/compression/error_bound.h"
#include "armature/engine/io/asset.h"
#include "server/assets/bucket/bucket_mirror.h"
#include "server/assets/bucket/store_health.h"
#include "server/assets/catalog.h"
#include "server/rpc/limits.h"

namespace armature::server {

struct ImportRequest {
  std::string name;  // empty: the filename's stem
  std::string filename;
  std::string format;  // empty: detect
  bool replace = false;
  // Set: replace exactly this stored asset, ABORTED if `name` holds another
  // by the time the write lock is taken (a read-modify-write that lost a race).
  std::shared_ptr<const StoredAsset> replace_only;
  std::string bytes;
  ResourceMap resources;  // further files by uri (a .gltf's .bin buffers)
  std::string animates;   // a clip the server made for this skeleton (AssetRecord::animates)
  std::string precision;  // ImportAssetRequest.precision (ParseClipPrecision); empty: the store's
};

struct StoreOptions {
  Limits limits;  // what an import may contain (CheckAssetLimits)
  // How often the manifest is checked for other servers' writes; 0: never.
  std::chrono::milliseconds watch_interval{500};
  // Set: the assets live on this bucket, the data dir is its cache.
  std::shared_ptr<BucketMirror> bucket{};
  int keep_versions = 0;         // versions kept per name on the bucket; 0: all
  ClipPrecision clip_precision;  // an import's clips' precision unless it asks (--clip-error)
};

class AssetStore {
 public:
  // Opens (creating if needed) a data dir and loads every asset in its
  // manifest. Assets that no longer parse are logged and skipped, never deleted.
  static StatusOr<std::unique_ptr<AssetStore>> Open(const std::filesystem::path& data_dir, StoreOptions options = {});
  ~AssetStore();

  std::shared_ptr<const Catalog> Snapshot() const;

  // Parses, persists, then publishes. INVALID_ARGUMENT for bad files or
  // names, ALREADY_EXISTS for a taken name (unless replace),
  // RESOURCE_EXHAUSTED over a limit or on a full disk ("data dir <dir>: no
  // space left on device"; then nothing of the import is left on disk).
  StatusOr<std::shared_ptr<const StoredAsset>> Import(ImportRequest request);
  // Removes the asset owning `name` from the manifest, then its file. Works
  // on a full disk (see KeepReserve).
  StatusOr<std::shared_ptr<const StoredAsset>> Delete(std::string_view name);

  // True when the data dir had no manifest when opened (a first start).
  bool fresh() const { return fresh_; }
  const std::filesystem::path& data_dir() const { return dir_; }
  StoreHealth Health() const;

 private:
  // What identifies one version of the manifest file: every write renames a
  // new file over it, so the inode changes with each.
  struct ManifestStamp {
    bool exists = false;
    uint64_t device = 0, inode = 0;
    int64_t size = 0, mtime_ns = 0;
    bool operator==(const ManifestStamp&) const = default;
  };

  AssetStore(std::filesystem::path dir, StoreOptions options) : dir_(std::move(dir)), options_(std::move(options)) {}
  Status Load();
  // Bucket mode (asset_store_bucket.cc): the start, from the bucket or the cache.
  Status LoadFromBucket();
  // Brings the catalog up to date with the bucket's latest versions. Call
  // with write_mu_ held. UNAVAILABLE (the health updated) when unreachable.
  Status SyncBucketLocked();
  // Reads (from the cache, else the bucket) and parses one version.
  StatusOr<std::shared_ptr<const StoredAsset>> LoadVersion(const VersionRecord& version);
  // The version's record, then LoadVersion; null for a tombstone.
  StatusOr<std::shared_ptr<const StoredAsset>> LoadNamedVersion(const std::string& name, const std::string& version);
  // What a write does first: the latest state, or why writes fail now.
  Status SyncBeforeWrite();
  // The bucket write of an import, then the cache's.
  Status PersistToBucket(AssetRecord& record, const ImportRequest& request, const Catalog& catalog);
  Status DeleteOnBucket(const AssetRecord& gone, const Catalog& catalog);
  // The cache's index and files after a bucket change; failures only logged.
  void WriteCache(const Catalog& catalog);
  void NoteReachable(const Status& status);
  static StatusOr<AssetContents> LoadContents(const std::filesystem::path& dir, const AssetRecord& r,
                                              const StoreOptions& options);
  // Brings the published catalog up to date with the manifest on disk.
  // Call with write_mu_ and a DataDirLock held. `referenced`, when given,
  // receives every file the manifest names (loadable or not).
  Status SyncLocked(std::set<std::filesystem::path>* referenced = nullptr);
  // Call with the exclusive DataDirLock held.
  void RemoveLeftovers(const std::set<std::filesystem::path>& referenced) const;
  // The reserve: space (a preallocated file) that only a delete may use, so
  // that a disk filled by imports never blocks the delete that frees it.
  void KeepReserve() const;
  bool ReleaseReserve() const;  // true if there was one to release
  ManifestStamp StampOfManifest() const;
  Status WriteManifest(const Catalog& catalog);
  void Publish(std::shared_ptr<const Catalog> catalog);
  // Reloads the manifest if another server changed it since this one last
  // read or wrote it. The watcher calls it every watch_interval.
  void Refresh();
  void Watch();

  std::filesystem::path dir_;
  StoreOptions options_;
  bool fresh_ = false;
  std::mutex write_mu_;             // one writer or reload at a time in this process
  ManifestStamp stamp_;             // of the manifest the catalog reflects; guarded by write_mu_
  std::string last_refresh_error_;  // logged once, not every poll; guarded by write_mu_
  // Manifest entries (name, JSON text) that could not be loaded: written back
  // with every new manifest, so an asset that does not load here (a newer
  // replica's format, a file being repaired) is never dropped; guarded by write_mu_.
  std::vector<std::pair<std::string, std::string>> unloaded_entries_;
  mutable std::mutex snapshot_mu_;
  std::shared_ptr<const Catalog> catalog_;

  // Bucket mode; guarded by write_mu_ but health_, which health_mu_ guards.
  std::map<std::string, std::string> latest_seen_;  // name → its latest version, tombstones too
  // "name/version" not to read again: their records and objects are immutable.
  std::set<std::string> tombstones_;
  std::set<std::string> failed_versions_;  // unreadable, corrupt or not parsing
  mutable std::mutex health_mu_;
  StoreHealth health_;
  std::chrono::steady_clock::time_point last_sync_{};

  std::mutex watch_mu_;
  std::condition_variable watch_cv_;
  bool stopping_ = false;
  std::thread watcher_;
};

// Asset names become file names: letters, digits, '.', '_' and '-', not
// starting with '.', at most 128 characters.
Status ValidateAssetName(std::string_view name);

}  // namespace armature::server
