#include "server/assets/asset_store.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <ctime>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "server/assets/asset_limits.h"
#include "server/assets/asset_memory.h"
#include "server/assets/asset_record_json.h"
#include "server/assets/runtime_clips.h"
#include "server/assets/data_dir_lock.h"
#include "server/assets/file_io.h"
#include "server/assets/part_deletion.h"

namespace armature::server {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr char kManifest[] = "manifest.json";
// Space held back so that a delete can always write its (smaller) manifest,
// however full imports have made the disk.
constexpr char kReserve[] = ".space-reserve";
constexpr int64_t kReserveMinBytes = 64 << 10;

std::string NowRfc3339() {
  const auto now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string StemOf(std::string_view filename) {
  std::string base(filename);
  if (auto slash = base.find_last_of("/\\"); slash != std::string::npos) base = base.substr(slash + 1);
  if (auto dot = base.rfind('.'); dot != std::string::npos && dot > 0) base = base.substr(0, dot);
  return base;
}

// A file name for a stored resource uri ("textures/a b.bin" → "a_b.bin").
std::string SafeFileName(std::string_view uri) {
  std::string out;
  for (char c : uri.substr(uri.find_last_of("/\\") == std::string_view::npos ? 0 : uri.find_last_of("/\\") + 1))
    out += (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_') ? c : '_';
  return out.empty() ? "resource" : out;
}

// The same stored files: stored names are unique per import, so equal
// records mean equal contents and the parsed asset can be kept.
bool SameStoredFiles(const AssetRecord& a, const AssetRecord& b) {
  return a.format == b.format && a.file == b.file && a.resources == b.resources && a.animates == b.animates &&
         a.precision == b.precision;
}

}  // namespace

// Reads a stored asset's files back and parses them.
StatusOr<AssetContents> AssetStore::LoadContents(const fs::path& dir, const AssetRecord& r,
                                                 const StoreOptions& options) {
  const Limits& limits = options.limits;
  ARMATURE_ASSIGN_OR_RETURN(auto bytes, ReadFile(dir / r.file));
  ResourceMap resources;
  for (const auto& [uri, file] : r.resources) {
    ARMATURE_ASSIGN_OR_RETURN(auto data, ReadFile(dir / file));
    resources.emplace(uri, std::move(data));
  }
  auto contents = WithLimitFlags(ParseAsset(r.format, bytes, r.name, resources, LoadLimitsOf(limits)));
  if (!contents.ok()) return contents;
  ARMATURE_RETURN_IF_ERROR(AdoptDerivedClip(r, *contents));
  ARMATURE_ASSIGN_OR_RETURN(
      const ClipPrecision precision,
      ParseClipPrecision(r.precision, "manifest entry '" + r.name + "': precision", options.clip_precision));
  ARMATURE_RETURN_IF_ERROR(CompressClips(*contents, precision));
  return contents;
}

Status ValidateAssetName(std::string_view name) {
  if (name.empty()) return Status::InvalidArgument("name: must not be empty");
  if (name.size() > 128) return Status::InvalidArgument("name: longer than 128 characters");
  if (name.front() == '.') return Status::InvalidArgument("name: must not start with '.'");
  for (char c : name) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-'))
      return Status::InvalidArgument("name: '" + std::string(name) +
                                     "' may only use letters, digits, '.', '_' and '-' (no '/', no NUL)");
  }
  return Status::Ok();
}

StatusOr<std::unique_ptr<AssetStore>> AssetStore::Open(const fs::path& data_dir, StoreOptions options) {
  std::error_code ec;
  fs::create_directories(data_dir / "files", ec);
  if (ec) return Status::FailedPrecondition("cannot create data dir " + data_dir.string() + ": " + ec.message());
  std::unique_ptr<AssetStore> store(new AssetStore(fs::absolute(data_dir), std::move(options)));
  ARMATURE_RETURN_IF_ERROR(store->options_.bucket ? store->LoadFromBucket() : store->Load());
  if (store->options_.watch_interval.count() > 0) store->watcher_ = std::thread([s = store.get()] { s->Watch(); });
  return store;
}

AssetStore::~AssetStore() {
  {
    std::lock_guard lock(watch_mu_);
    stopping_ = true;
  }
  watch_cv_.notify_all();
  if (watcher_.joinable()) watcher_.join();
}

Status AssetStore::Load() {
  std::lock_guard write_lock(write_mu_);
  auto lock = DataDirLock::Acquire(dir_, DataDirLock::Mode::kExclusive);
  if (!lock.ok()) return lock.status();
  fresh_ = !fs::exists(dir_ / kManifest);
  std::set<fs::path> referenced;
  ARMATURE_RETURN_IF_ERROR(SyncLocked(&referenced));
  RemoveLeftovers(referenced);
  KeepReserve();
  spdlog::info("loaded {} assets from {}", Snapshot()->assets.size(), dir_.string());
  return Status::Ok();
}

AssetStore::ManifestStamp AssetStore::StampOfManifest() const {
  // open + fstat rather than stat: on NFS, opening revalidates the cached
  // attributes (close-to-open consistency), so another host's write shows.
  ManifestStamp stamp;
  const int fd = ::open((dir_ / kManifest).c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return stamp;
  struct stat st {};
  if (::fstat(fd, &st) == 0) {
    stamp.exists = true;
    stamp.device = st.st_dev;
    stamp.inode = st.st_ino;
    stamp.size = st.st_size;
    stamp.mtime_ns = static_cast<int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
  }
  ::close(fd);
  return stamp;
}

Status AssetStore::SyncLocked(std::set<fs::path>* referenced) {
  const ManifestStamp stamp = StampOfManifest();
  const bool first = Snapshot() == nullptr;
  if (!first && stamp == stamp_ && referenced == nullptr) return Status::Ok();
  const auto current = first ? std::make_shared<const Catalog>() : Snapshot();
  std::map<std::string, std::shared_ptr<const StoredAsset>> assets;
  std::vector<std::pair<std::string, std::string>> unloaded;
  auto keep_unloaded = [&](const json& entry) {
    const json* name = entry.is_object() && entry.contains("name") ? &entry["name"] : nullptr;
    unloaded.emplace_back(name && name->is_string() ? name->get<std::string>() : "", entry.dump());
  };
  if (stamp.exists) {
    ARMATURE_ASSIGN_OR_RETURN(auto text, ReadFile(dir_ / kManifest));
    json j = json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.contains("assets") || !j["assets"].is_array())
      return Status::FailedPrecondition((dir_ / kManifest).string() + " is not a valid manifest");
    for (const json& entry : j["assets"]) {
      auto record = RecordFromJson(entry);
      if (const Status valid = record.ok() ? CheckRecordPaths(*record) : record.status(); !valid.ok()) {
        spdlog::error("manifest: skipping an entry: {}", valid.message());
        keep_unloaded(entry);
        continue;
      }
      if (referenced != nullptr) {
        referenced->insert(dir_ / record->file);
        for (const auto& [uri, file] : record->resources) referenced->insert(dir_ / file);
      }
      if (auto it = current->assets.find(record->name);
          it != current->assets.end() && SameStoredFiles(it->second->record, *record)) {
        assets[record->name] = it->second;  // unchanged: keep the parsed asset
        continue;
      }
      auto contents = LoadContents(dir_, *record, options_);
      if (!contents.ok()) {
        spdlog::error("asset '{}' ({}) could not be loaded and is skipped: {}", record->name, record->file,
                      contents.status().message());
        keep_unloaded(entry);
        continue;
      }
      assets[record->name] = std::make_shared<const StoredAsset>(StoredAsset{*record, std::move(*contents)});
    }
  }
  if (!first) {
    for (const auto& [name, asset] : assets)
      if (!current->assets.contains(name) || current->assets.at(name) != asset)
        spdlog::info("manifest changed: asset '{}' loaded", name);
    for (const auto& [name, asset] : current->assets)
      if (!assets.contains(name)) spdlog::info("manifest changed: asset '{}' removed", name);
  }
  ARMATURE_ASSIGN_OR_RETURN(auto catalog, BuildCatalog(std::move(assets)));
  Publish(std::move(catalog));
  unloaded_entries_ = std::move(unloaded);
  stamp_ = stamp;
  return Status::Ok();
}

void AssetStore::RemoveLeftovers(const std::set<fs::path>& referenced) const {
  // Leftovers of interrupted writes (a killed server, a full disk):
  // temporary files, and stored files that no manifest entry took in. Every
  // writer writes files and manifest while holding the exclusive data dir
  // lock, and so do we now: no server is between those writes, so whatever
  // no manifest entry names is a leftover, however young.
  for (const fs::path& d : {dir_, dir_ / "files"}) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(d, ec)) {
      const std::string fname = entry.path().filename().string();
      const bool temporary = fname.starts_with(".") && fname.find(".tmp-") != std::string::npos;
      const bool orphan = d != dir_ && !referenced.contains(entry.path());
      if (!entry.is_regular_file(ec) || !(temporary || orphan)) continue;
      spdlog::warn("removing leftover of an interrupted write: {}", entry.path().string());
      fs::remove(entry.path(), ec);
    }
  }
}

void AssetStore::KeepReserve() const {
  const fs::path path = dir_ / kReserve;
  std::error_code ec;
  const auto manifest_size = fs::file_size(dir_ / kManifest, ec);
  const int64_t wanted = kReserveMinBytes + (ec ? 0 : 2 * static_cast<int64_t>(manifest_size));
  const auto have = fs::file_size(path, ec);
  if (!ec && static_cast<int64_t>(have) >= wanted) return;
  if (!AllocateFile(path, wanted)) spdlog::debug("no room for the delete reserve in {} (yet)", dir_.string());
}

bool AssetStore::ReleaseReserve() const {
  std::error_code ec;
  const bool had = fs::remove(dir_ / kReserve, ec);
  if (had) spdlog::warn("data dir {} is full: using the reserve to write the manifest", dir_.string());
  return had;
}

void AssetStore::Refresh() {
  std::lock_guard write_lock(write_mu_);
  if (options_.bucket) {
    auto lock = DataDirLock::Acquire(dir_, DataDirLock::Mode::kExclusive);  // the cache is written too
    if (lock.ok()) (void)SyncBucketLocked();                                // failures are logged and in the health
    return;
  }
  if (StampOfManifest() == stamp_) return;
  auto lock = DataDirLock::Acquire(dir_, DataDirLock::Mode::kShared);
  const Status st = lock.ok() ? SyncLocked() : lock.status();
  // Keep serving what is loaded; say so once per distinct problem.
  if (!st.ok() && st.message() != last_refresh_error_)
    spdlog::error("cannot reload the manifest, keeping the assets loaded: {}", st.message());
  last_refresh_error_ = st.ok() ? "" : st.message();
}

void AssetStore::Watch() {
  std::unique_lock lock(watch_mu_);
  while (!watch_cv_.wait_for(lock, options_.watch_interval, [this] { return stopping_; })) {
    lock.unlock();
    Refresh();
    lock.lock();
  }
}

std::shared_ptr<const Catalog> AssetStore::Snapshot() const {
  std::lock_guard lock(snapshot_mu_);
  return catalog_;
}

void AssetStore::Publish(std::shared_ptr<const Catalog> catalog) {
  std::lock_guard lock(snapshot_mu_);
  catalog_ = std::move(catalog);
}

Status AssetStore::WriteManifest(const Catalog& catalog) {
  json entries = json::array();
  for (const auto& [name, asset] : catalog.assets) entries.push_back(RecordToJson(asset->record));
  // An import under the same name replaces an entry that did not load.
  const auto replaced = [&](const auto& unloaded) { return catalog.assets.contains(unloaded.first); };
  for (const auto& entry : unloaded_entries_)
    if (!replaced(entry)) entries.push_back(json::parse(entry.second));
  const json j = {{"version", 1}, {"assets", entries}};
  ARMATURE_RETURN_IF_ERROR(WriteFileAtomic(dir_, kManifest, j.dump(2)));
  std::erase_if(unloaded_entries_, replaced);
  stamp_ = StampOfManifest();  // this server's own write needs no reload
  return Status::Ok();
}

StatusOr<std::shared_ptr<const StoredAsset>> AssetStore::Import(ImportRequest request) {
  if (request.name.empty()) request.name = StemOf(request.filename);
  ARMATURE_RETURN_IF_ERROR(ValidateAssetName(request.name));
  if (request.bytes.empty()) return Status::InvalidArgument("data: the file is empty");
  ARMATURE_ASSIGN_OR_RETURN(auto format, DetectFormat(request.format, request.filename, request.bytes));
  const std::string label = request.filename.empty() ? request.name : request.filename;
  // Decoding stops at the room left under --max-assets-mb (what a replace
  // frees counted as room); checked exactly under the write lock below.
  const auto before = Snapshot();
  const auto replacing = request.replace ? before->assets.find(request.name) : before->assets.end();
  const size_t held = HeldAssetBytes(*before, replacing == before->assets.end() ? nullptr : replacing->second.get());
  auto contents = WithLimitFlags(
      ParseAsset(format, request.bytes, request.name, request.resources, ImportLimitsWithRoom(options_.limits, held)));
  if (!contents.ok()) return contents.status().WithContext(label + ": ");
  ARMATURE_RETURN_IF_ERROR(CheckAssetLimits(*contents, options_.limits).WithContext(label + ": "));
  AssetRecord record;
  record.name = request.name;
  record.animates = request.animates;
  ARMATURE_RETURN_IF_ERROR(AdoptDerivedClip(record, *contents));
  ARMATURE_ASSIGN_OR_RETURN(const ClipPrecision precision,
                            ParseClipPrecision(request.precision, "precision", options_.clip_precision));
  record.precision = ClipPrecisionText(precision);
  // Before the write lock: other writers need not wait for it.
  ARMATURE_RETURN_IF_ERROR(CompressClips(*contents, precision).WithContext(label + ": "));

  // Read-modify-write of the manifest, exclusive across every server on this data dir.
  std::lock_guard write_lock(write_mu_);
  auto dir_lock = DataDirLock::Acquire(dir_, DataDirLock::Mode::kExclusive);
  if (!dir_lock.ok()) return dir_lock.status();
  ARMATURE_RETURN_IF_ERROR(SyncBeforeWrite());
  const auto current = Snapshot();
  auto assets = current->assets;
  std::shared_ptr<const StoredAsset> replaced;
  if (auto it = assets.find(request.name); it != assets.end()) {
    if (!request.replace)
      return Status::AlreadyExists("asset '" + request.name + "' already exists (set replace to overwrite it)");
    replaced = it->second;
    assets.erase(it);
  }
  if (request.replace_only && replaced != request.replace_only)
    return Status::Aborted("asset '" + request.name + "' changed while this edit was made from it");
  ARMATURE_RETURN_IF_ERROR(
      CheckAssetsTotal(EstimateAssetBytes(*contents), HeldAssetBytes(*current, replaced.get()), options_.limits)
          .WithContext(label + ": "));
  record.format = format;
  record.filename = request.filename;
  record.size_bytes = static_cast<int64_t>(request.bytes.size());
  record.imported_at = NowRfc3339();
  const auto seen = latest_seen_.find(record.name);
  record.version = NewVersion(seen == latest_seen_.end() ? "" : seen->second);
  const std::string unique = options_.bucket ? record.version : RandomSuffix();
  record.file = "files/" + request.name + "." + unique + std::string(FormatExtension(format));
  // Each resource's file carries its index: two uris may end alike ("a/data.bin",
  // "b/data.bin"; "a b.bin", "a_b.bin") and must not share a file.
  int index = 0;
  for (const auto& [uri, data] : request.resources) {
    record.resources[uri] =
        "files/" + request.name + "." + unique + ".res" + std::to_string(index++) + "." + SafeFileName(uri);
    record.size_bytes += static_cast<int64_t>(data.size());
  }
  auto stored = std::make_shared<const StoredAsset>(StoredAsset{record, std::move(*contents)});
  assets[record.name] = stored;
  auto catalog = BuildCatalog(std::move(assets));  // catches part-name clashes with other assets
  if (!catalog.ok()) return catalog.status();
  if (options_.bucket) {
    ARMATURE_RETURN_IF_ERROR(PersistToBucket(record, request, **catalog).WithContext(label + ": "));
    Publish(std::move(*catalog));
    spdlog::info("imported asset '{}' version {} ({}, {} bytes)", record.name, record.version,
                 FormatName(record.format), record.size_bytes);
    return stored;
  }

  // Persist the files, then the manifest that makes them part of the store.
  // On any failure (a full disk) everything this import wrote goes again.
  std::vector<std::string> written;
  auto persist = [&]() -> Status {
    ARMATURE_RETURN_IF_ERROR(WriteFileAtomic(dir_, record.file, request.bytes));
    written.push_back(record.file);
    for (const auto& [uri, file] : record.resources) {
      ARMATURE_RETURN_IF_ERROR(WriteFileAtomic(dir_, file, request.resources.find(uri)->second));
      written.push_back(file);
    }
    return WriteManifest(**catalog);
  };
  if (Status st = persist(); !st.ok()) {
    std::error_code ec;
    for (const std::string& file : written) fs::remove(dir_ / file, ec);
    spdlog::error("import of '{}' failed, its files removed: {}", record.name, st.message());
    return st.WithContext(label + ": ");
  }
  Publish(std::move(*catalog));
  if (replaced) {
    std::error_code ec;
    fs::remove(dir_ / replaced->record.file, ec);
    for (const auto& [uri, file] : replaced->record.resources) fs::remove(dir_ / file, ec);
  }
  KeepReserve();
  spdlog::info("imported asset '{}' ({}, {} bytes)", record.name, FormatName(record.format), record.size_bytes);
  return stored;
}

StatusOr<std::shared_ptr<const StoredAsset>> AssetStore::Delete(std::string_view name) {
  std::lock_guard write_lock(write_mu_);
  auto dir_lock = DataDirLock::Acquire(dir_, DataDirLock::Mode::kExclusive);
  if (!dir_lock.ok()) return dir_lock.status();
  ARMATURE_RETURN_IF_ERROR(SyncBeforeWrite());
  const auto current = Snapshot();
  ARMATURE_ASSIGN_OR_RETURN(auto owner, current->FindOwner(name));
  ARMATURE_RETURN_IF_ERROR(CheckDeletionTakesOnly(*owner, name));
  auto assets = current->assets;
  assets.erase((owner)->record.name);
  ARMATURE_ASSIGN_OR_RETURN(auto catalog, BuildCatalog(std::move(assets)));
  const AssetRecord& gone = (owner)->record;
  if (options_.bucket) {
    ARMATURE_RETURN_IF_ERROR(DeleteOnBucket(gone, *catalog));
    Publish(std::move(catalog));
    spdlog::info("deleted asset '{}'", gone.name);
    return owner;
  }
  auto remove_files = [&] {
    std::error_code ec;
    fs::remove(dir_ / gone.file, ec);
    for (const auto& [uri, file] : gone.resources) fs::remove(dir_ / file, ec);
  };
  Status st = WriteManifest(*catalog);
  // A full disk must not keep anything from being deleted: the reserve
  // makes room for the new manifest, which is smaller than the old one.
  if (st.code() == StatusCode::kResourceExhausted && ReleaseReserve()) st = WriteManifest(*catalog);
  if (st.code() == StatusCode::kResourceExhausted) {
    // No reserve left (another server used it): free the asset's own files
    // first. Should the manifest still not fit, its entry stays, now naming
    // missing files, and is reported (and kept) as unloadable at the next start.
    spdlog::warn("data dir full: removing the files of '{}' before its manifest entry", gone.name);
    remove_files();
    st = WriteManifest(*catalog);
  }
  if (!st.ok()) return st;
  Publish(std::move(catalog));
  remove_files();
  KeepReserve();
  spdlog::info("deleted asset '{}'", gone.name);
  return owner;
}

}  // namespace armature::server
