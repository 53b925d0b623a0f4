// Factored deformers kept between unary Deform calls. A browser drags a
// vertex by calling Deform again and again with the same mesh, setup and
// handle indices and new handle positions; with the factorization cached,
// each call after the first only back-substitutes.
//
// Key: the mesh's identity in the catalog (the StoredAsset and the part it
// owns, both kept alive by the entry, so their addresses cannot be reused by
// another asset while the entry exists), its name, the setup as
// deterministically serialized protobuf (a field added to DeformSetup later
// joins the key by itself) and the handle indices in request order. A lookup
// resolves the name in the current catalog first, so a mesh deleted or
// re-imported under the same name never meets an old entry; entries whose
// mesh left the catalog are dropped the first time a lookup sees a newer
// catalog.
//
// Bounded by bytes (MeshDeformer::memory_bytes: the factor's nonzeros as the
// engine counts them after the symbolic analysis, the handle basis and the
// Laplacian model), least recently used out first. A deformer larger than the
// whole budget is used for its call and not kept. Deformers are shared and
// solved with the const MeshDeformer::SolveFresh, so calls on one entry run
// in parallel and get the answer a freshly factored deformer would give
// (ARAP included: it starts from the rest shape, not from the last call's
// result). Factoring happens outside the lock; two concurrent misses of one
// key both factor and the first to finish is kept.
#pragma once

#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "armature/base/status.h"
#include "armature/v1/deform.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"
#include "server/deform/mesh_deformer.h"
#include "server/rpc/metrics.h"

namespace armature::server {

struct DeformerCacheStats {
  uint64_t hits = 0;
  uint64_t misses = 0;  // lookups that built a deformer (including those that failed, and all with the cache off)
  size_t bytes = 0;     // memory_bytes of the deformers kept
  size_t entries = 0;
};

class DeformerCache {
 public:
  explicit DeformerCache(size_t max_bytes) : max_bytes_(max_bytes) {}

  // The deformer for this mesh (in `catalog`), setup and handle indices:
  // the cached one, or MeshDeformer::Create's (its errors are returned and
  // nothing is kept).
  StatusOr<std::shared_ptr<const MeshDeformer>> Get(const std::shared_ptr<const Catalog>& catalog, const Limits& limits,
                                                    const v1::DeformSetup& setup, std::vector<uint32_t> handles);

  DeformerCacheStats stats() const;
  // armature_deform_cache_hits_total, _misses_total and armature_deform_cache_bytes.
  void Collect(PrometheusText& out) const;

 private:
  struct Entry {
    std::string key;
    std::shared_ptr<const MeshDeformer> deformer;
    size_t bytes = 0;
  };
  using Lru = std::list<Entry>;  // most recently used first

  // Drops entries whose mesh is no longer the one `catalog` has under its
  // name. Called with mu_ held, when the catalog is not the one last seen.
  void DropStaleLocked(const Catalog& catalog);
  Lru::iterator EraseLocked(Lru::iterator it);  // returns the next entry

  const size_t max_bytes_;
  mutable std::mutex mu_;
  Lru lru_;
  std::unordered_map<std::string_view, Lru::iterator> index_;  // views of the entries' keys
  std::weak_ptr<const Catalog> seen_;                          // the catalog of the last lookup
  size_t bytes_ = 0;
  uint64_t hits_ = 0, misses_ = 0;
};

}  // namespace armature::server
