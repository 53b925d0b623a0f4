// AssetStore's bucket mode (--store): the bucket is the truth, the data dir
// its cache. See asset_store.h and bucket/bucket_layout.h.
#include <spdlog/spdlog.h>

#include "server/assets/asset_store.h"
#include "server/assets/data_dir_lock.h"
#include "server/assets/file_io.h"

namespace armature::server {
namespace fs = std::filesystem;
namespace {

constexpr char kManifest[] = "manifest.json";

std::string Latest(const std::map<std::string, std::string>& latest, const std::string& name) {
  auto it = latest.find(name);
  return it == latest.end() ? "" : it->second;
}

}  // namespace

StoreHealth AssetStore::Health() const {
  std::lock_guard lock(health_mu_);
  StoreHealth health = health_;
  if (!options_.bucket) {
    health.kind = "data_dir";
    health.location = dir_.string();
    return health;
  }
  health.kind = "bucket";
  health.location = options_.bucket->Describe();
  health.seconds_since_sync =
      last_sync_ == std::chrono::steady_clock::time_point{}
          ? -1
          : std::chrono::duration<double>(std::chrono::steady_clock::now() - last_sync_).count();
  return health;
}

void AssetStore::NoteReachable(const Status& status) {
  const bool reachable =
      status.ok() || (status.code() != StatusCode::kUnavailable && status.code() != StatusCode::kPermissionDenied &&
                      status.code() != StatusCode::kFailedPrecondition);
  std::lock_guard lock(health_mu_);
  if (reachable) {
    if (!health_.reachable) spdlog::info("object store {} is reachable again", options_.bucket->Describe());
    last_sync_ = std::chrono::steady_clock::now();
    health_.reachable = true;
    health_.error.clear();
    return;
  }
  if (health_.reachable || health_.error != status.message())
    spdlog::error(
        "object store unavailable, serving the {} assets loaded; imports and deletes fail until it is back: {}",
        Snapshot() ? Snapshot()->assets.size() : 0, status.message());
  health_.reachable = false;
  health_.error = status.message();
}

Status AssetStore::LoadFromBucket() {
  std::lock_guard write_lock(write_mu_);
  ARMATURE_ASSIGN_OR_RETURN(auto lock, DataDirLock::Acquire(dir_, DataDirLock::Mode::kExclusive));
  const bool cached = fs::exists(dir_ / kManifest);
  // A warm cache first: the bucket's versions that it holds need neither a download nor a record read.
  if (cached)
    if (Status st = SyncLocked(); !st.ok())
      spdlog::warn("the cache in {} is not used: {}", dir_.string(), st.message());
  const Status st = SyncBucketLocked();
  if (st.ok()) {
    fresh_ = latest_seen_.empty();
    spdlog::info("loaded {} assets from {} (cache: {})", Snapshot()->assets.size(), options_.bucket->Describe(),
                 dir_.string());
    return Status::Ok();
  }
  // Denied credentials or a missing bucket are a configuration to fix now, not an outage to wait out.
  if (st.code() != StatusCode::kUnavailable || !cached)
    return Status(st.code(), "cannot start: " + st.message() +
                                 (st.code() == StatusCode::kUnavailable
                                      ? " (and " + dir_.string() + " holds no cache of it to serve from)"
                                      : ""));
  if (!Snapshot()) ARMATURE_RETURN_IF_ERROR(SyncLocked());
  {
    std::lock_guard health_lock(health_mu_);
    health_.serving_cache = true;
  }
  spdlog::warn("object store {} unreachable at start: serving the {} cached assets of {} until it is back: {}",
               options_.bucket->Describe(), Snapshot()->assets.size(), dir_.string(), st.message());
  return Status::Ok();
}

StatusOr<std::shared_ptr<const StoredAsset>> AssetStore::LoadVersion(const VersionRecord& version) {
  const AssetRecord& r = version.record;
  auto fetch = [&](const std::string& file, const StoredObject& object) -> Status {
    std::error_code ec;
    // Cache files are written whole (atomically) and only after their hash was checked.
    if (fs::exists(dir_ / file, ec) && static_cast<int64_t>(fs::file_size(dir_ / file, ec)) == object.size && !ec)
      return Status::Ok();
    ARMATURE_ASSIGN_OR_RETURN(std::string bytes, options_.bucket->ReadObject(object));
    return WriteFileAtomic(dir_, file, bytes);
  };
  ARMATURE_RETURN_IF_ERROR(fetch(r.file, version.source));
  for (const auto& [uri, file] : r.resources) ARMATURE_RETURN_IF_ERROR(fetch(file, version.resources.at(uri)));
  ARMATURE_ASSIGN_OR_RETURN(auto contents, LoadContents(dir_, r, options_));
  return std::make_shared<const StoredAsset>(StoredAsset{r, std::move(contents)});
}

StatusOr<std::shared_ptr<const StoredAsset>> AssetStore::LoadNamedVersion(const std::string& name,
                                                                          const std::string& version) {
  ARMATURE_ASSIGN_OR_RETURN(VersionRecord record, options_.bucket->ReadRecord(name, version));
  if (record.deleted) {
    tombstones_.insert(name + "/" + version);
    return std::shared_ptr<const StoredAsset>();
  }
  return LoadVersion(record);
}

Status AssetStore::SyncBucketLocked() {
  auto versions = options_.bucket->Versions();
  NoteReachable(versions.status());
  if (!versions.ok()) return versions.status();
  const auto current = Snapshot() ? Snapshot() : std::make_shared<const Catalog>();
  std::map<std::string, std::shared_ptr<const StoredAsset>> assets;
  std::map<std::string, std::string> latest;
  for (const auto& [name, list] : *versions) {
    latest[name] = list.back();
    const auto held = current->assets.find(name);
    // The newest version that loads, walking back past those that do not
    // (a replica that held one keeps it; a new one finds the same).
    bool tombstoned = false;
    for (auto v = list.rbegin(); v != list.rend() && !assets.contains(name) && !tombstoned; ++v) {
      const std::string& version = *v;
      if (held != current->assets.end() && held->second->record.version == version) {
        assets[name] = held->second;
        break;
      }
      tombstoned = tombstones_.contains(name + "/" + version);
      if (tombstoned) break;
      if (failed_versions_.contains(name + "/" + version)) continue;
      auto loaded = LoadNamedVersion(name, version);
      if (!loaded.ok() && loaded.status().code() == StatusCode::kUnavailable) {
        NoteReachable(loaded.status());
        return loaded.status();  // an outage, not a bad version: all again at the next poll
      }
      if (loaded.ok()) {
        tombstoned = *loaded == nullptr;  // a tombstone: the name is free
        if (!tombstoned) assets[name] = *loaded;
        continue;
      }
      failed_versions_.insert(name + "/" + version);
      {
        std::lock_guard health_lock(health_mu_);
        ++health_.version_failures;
      }
      spdlog::error("version {} of asset '{}' is skipped, never served: {}", version, name, loaded.status().message());
    }
    // Nothing newer loads (the versions before were pruned): what is held keeps serving.
    if (!assets.contains(name) && !tombstoned && held != current->assets.end()) assets[name] = held->second;
  }
  latest_seen_ = std::move(latest);
  const bool same = assets == current->assets && Snapshot() != nullptr;
  if (same) return Status::Ok();
  for (const auto& [name, asset] : assets)
    if (!current->assets.contains(name) || current->assets.at(name) != asset)
      spdlog::info("bucket changed: asset '{}' version {} loaded", name, asset->record.version);
  for (const auto& [name, asset] : current->assets)
    if (!assets.contains(name)) spdlog::info("bucket changed: asset '{}' removed", name);
  auto catalog = BuildCatalog(std::move(assets));
  if (!catalog.ok()) {
    spdlog::error("the bucket's latest versions clash, keeping the assets loaded: {}", catalog.status().message());
    return Status::Ok();
  }
  Publish(*catalog);
  WriteCache(**catalog);
  return Status::Ok();
}

void AssetStore::WriteCache(const Catalog& catalog) {
  unloaded_entries_.clear();  // the bucket holds every version: the cache keeps only what loads
  if (Status st = WriteManifest(catalog); !st.ok()) spdlog::warn("could not write the cache's index: {}", st.message());
  std::set<fs::path> referenced;
  for (const auto& [name, asset] : catalog.assets) {
    referenced.insert(dir_ / asset->record.file);
    for (const auto& [uri, file] : asset->record.resources) referenced.insert(dir_ / file);
  }
  RemoveLeftovers(referenced);
}

Status AssetStore::SyncBeforeWrite() {
  if (!options_.bucket) return SyncLocked();
  const Status st = SyncBucketLocked();
  if (st.code() == StatusCode::kUnavailable || st.code() == StatusCode::kFailedPrecondition ||
      st.code() == StatusCode::kPermissionDenied)
    return Status::Unavailable("the asset store is unavailable, so imports and deletes fail until it is back (" +
                               std::to_string(Snapshot()->assets.size()) +
                               " assets loaded are still served): " + st.message());
  return st;
}

Status AssetStore::PersistToBucket(AssetRecord& record, const ImportRequest& request, const Catalog& catalog) {
  VersionRecord version;
  version.record = record;
  if (Status st = options_.bucket->WriteVersion(version, request.bytes, request.resources); !st.ok()) {
    NoteReachable(st);
    return st.code() == StatusCode::kUnavailable
               ? Status::Unavailable("the asset store is unavailable, nothing was imported: " + st.message())
               : st;
  }
  // Acknowledged from here: the version is on the bucket. The cache follows, best effort.
  latest_seen_[record.name] = record.version;
  if (Status st = WriteFileAtomic(dir_, record.file, request.bytes); !st.ok())
    spdlog::warn("could not cache '{}': {}", record.name, st.message());
  for (const auto& [uri, file] : record.resources)
    if (Status st = WriteFileAtomic(dir_, file, request.resources.find(uri)->second); !st.ok())
      spdlog::warn("could not cache '{}': {}", record.name, st.message());
  WriteCache(catalog);
  if (options_.keep_versions > 0) options_.bucket->Prune(record.name, options_.keep_versions);
  return Status::Ok();
}

Status AssetStore::DeleteOnBucket(const AssetRecord& gone, const Catalog& catalog) {
  const std::string version = NewVersion(Latest(latest_seen_, gone.name));
  if (Status st = options_.bucket->WriteTombstone(gone.name, version); !st.ok()) {
    NoteReachable(st);
    return st.code() == StatusCode::kUnavailable
               ? Status::Unavailable("the asset store is unavailable, nothing was deleted: " + st.message())
               : st;
  }
  latest_seen_[gone.name] = version;
  WriteCache(catalog);
  if (options_.keep_versions > 0) options_.bucket->Prune(gone.name, options_.keep_versions);
  return Status::Ok();
}

}  // namespace armature::server
