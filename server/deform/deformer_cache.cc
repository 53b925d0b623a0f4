#include "server/deform/deformer_cache.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>

#include <iterator>

namespace armature::server {
namespace {

template <class T>
void AppendRaw(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

// The asset and part addresses, the setup's length and deterministic bytes,
// then the handle indices: no two different lookups share a key.
std::string KeyOf(const PartRef<NamedMesh>& mesh, const v1::DeformSetup& setup, const std::vector<uint32_t>& handles) {
  std::string setup_bytes;
  {
    google::protobuf::io::StringOutputStream stream(&setup_bytes);
    google::protobuf::io::CodedOutputStream coded(&stream);
    coded.SetSerializationDeterministic(true);
    setup.SerializeToCodedStream(&coded);
  }
  std::string key;
  key.reserve(3 * sizeof(uint64_t) + setup_bytes.size() + handles.size() * sizeof(uint32_t));
  AppendRaw(key, mesh.asset.get());
  AppendRaw(key, mesh.part);
  AppendRaw(key, static_cast<uint64_t>(setup_bytes.size()));
  key += setup_bytes;
  key.append(reinterpret_cast<const char*>(handles.data()), handles.size() * sizeof(uint32_t));
  return key;
}

StatusOr<std::shared_ptr<const MeshDeformer>> Make(const Catalog& catalog, const Limits& limits,
                                                   const v1::DeformSetup& setup, std::vector<uint32_t> handles) {
  auto made = MeshDeformer::Create(catalog, limits, setup, std::move(handles));
  if (!made.ok()) return made.status();
  return std::make_shared<const MeshDeformer>(std::move(*made));
}

}  // namespace

StatusOr<std::shared_ptr<const MeshDeformer>> DeformerCache::Get(const std::shared_ptr<const Catalog>& catalog,
                                                                 const Limits& limits, const v1::DeformSetup& setup,
                                                                 std::vector<uint32_t> handles) {
  auto mesh = catalog->FindMesh(setup.mesh());
  if (max_bytes_ == 0 || !mesh.ok()) {
    {
      std::lock_guard lock(mu_);
      ++misses_;
    }
    return Make(*catalog, limits, setup, std::move(handles));  // an unknown mesh's NOT_FOUND comes from here
  }
  std::string key = KeyOf(*mesh, setup, handles);
  {
    std::lock_guard lock(mu_);
    if (seen_.lock() != catalog) {
      DropStaleLocked(*catalog);
      seen_ = catalog;
    }
    if (auto it = index_.find(key); it != index_.end()) {
      ++hits_;
      lru_.splice(lru_.begin(), lru_, it->second);
      return it->second->deformer;
    }
    ++misses_;
  }
  // Factored without the lock: other entries stay usable meanwhile.
  auto made = Make(*catalog, limits, setup, std::move(handles));
  if (!made.ok()) return made.status();
  const size_t bytes = (*made)->memory_bytes() + key.size();
  std::lock_guard lock(mu_);
  if (auto it = index_.find(key); it != index_.end()) return it->second->deformer;  // a concurrent miss kept its own
  // Too big to keep, or the catalog changed while factoring (the entry may
  // already be stale, and DropStaleLocked ran for the newer catalog).
  if (bytes > max_bytes_ || seen_.lock() != catalog) return made;
  while (bytes_ + bytes > max_bytes_) EraseLocked(std::prev(lru_.end()));
  lru_.push_front(Entry{std::move(key), *made, bytes});
  index_.emplace(lru_.front().key, lru_.begin());
  bytes_ += bytes;
  return made;
}

void DeformerCache::DropStaleLocked(const Catalog& catalog) {
  for (auto it = lru_.begin(); it != lru_.end();) {
    const PartRef<NamedMesh>& mesh = it->deformer->mesh();
    const auto current = catalog.meshes.find(mesh.part->name);
    const bool stale = current == catalog.meshes.end() || current->second.part != mesh.part;
    it = stale ? EraseLocked(it) : std::next(it);
  }
}

DeformerCache::Lru::iterator DeformerCache::EraseLocked(Lru::iterator it) {
  index_.erase(it->key);
  bytes_ -= it->bytes;
  return lru_.erase(it);
}

DeformerCacheStats DeformerCache::stats() const {
  std::lock_guard lock(mu_);
  return {hits_, misses_, bytes_, lru_.size()};
}

void DeformerCache::Collect(PrometheusText& out) const {
  const DeformerCacheStats s = stats();
  out.Family("armature_deform_cache_hits_total", "counter",
             "Unary Deform calls answered with a cached factorization (same mesh, setup and handle indices).");
  out.Sample("armature_deform_cache_hits_total", {}, static_cast<double>(s.hits));
  out.Family("armature_deform_cache_misses_total", "counter",
             "Unary Deform calls that built and factored a deformer (all of them with --deform-cache-mb 0).");
  out.Sample("armature_deform_cache_misses_total", {}, static_cast<double>(s.misses));
  out.Family(
      "armature_deform_cache_bytes", "gauge",
      "Estimated memory of the cached deformers (factor, handle basis, Laplacian model), at most --deform-cache-mb.");
  out.Sample("armature_deform_cache_bytes", {}, static_cast<double>(s.bytes));
  out.Family("armature_deform_cache_entries", "gauge", "Deformers in the unary Deform cache.");
  out.Sample("armature_deform_cache_entries", {}, static_cast<double>(s.entries));
}

}  // namespace armature::server
