#include "server/assets/catalog.h"

#include <utility>

namespace armature::server {
namespace {

template <class Part>
Status IndexParts(const std::shared_ptr<const StoredAsset>& asset, const std::vector<Part>& parts,
                  std::map<std::string, PartRef<Part>>& index, std::string_view kind) {
  for (const Part& p : parts) {
    auto [it, inserted] = index.emplace(p.name, PartRef<Part>{asset, &p});
    if (!inserted)
      return Status::AlreadyExists(std::string(kind) + " '" + p.name + "' already exists (from asset '" +
                                   it->second.asset->record.name + "')");
  }
  return Status::Ok();
}

template <class Part>
StatusOr<PartRef<Part>> FindIn(const std::map<std::string, PartRef<Part>>& index, std::string_view name,
                               std::string_view kind) {
  auto it = index.find(std::string(name));
  if (it == index.end()) return Status::NotFound(std::string(kind) + " '" + std::string(name) + "' not found");
  return it->second;
}

}  // namespace

StatusOr<PartRef<NamedClip>> Catalog::FindClip(std::string_view name) const { return FindIn(clips, name, "clip"); }
StatusOr<PartRef<NamedSkeleton>> Catalog::FindSkeleton(std::string_view name) const {
  return FindIn(skeletons, name, "skeleton");
}
StatusOr<PartRef<NamedMesh>> Catalog::FindMesh(std::string_view name) const { return FindIn(meshes, name, "mesh"); }

StatusOr<std::shared_ptr<const StoredAsset>> Catalog::FindOwner(std::string_view name) const {
  const std::string key(name);
  if (auto it = assets.find(key); it != assets.end()) return it->second;
  if (auto it = clips.find(key); it != clips.end()) return it->second.asset;
  if (auto it = skeletons.find(key); it != skeletons.end()) return it->second.asset;
  if (auto it = meshes.find(key); it != meshes.end()) return it->second.asset;
  return Status::NotFound("no asset, clip, skeleton or mesh named '" + key + "'");
}

StatusOr<std::shared_ptr<Catalog>> BuildCatalog(std::map<std::string, std::shared_ptr<const StoredAsset>> assets) {
  auto c = std::make_shared<Catalog>();
  c->assets = std::move(assets);
  for (const auto& [name, asset] : c->assets) {
    ARMATURE_RETURN_IF_ERROR(IndexParts(asset, asset->contents.clips, c->clips, "clip"));
    ARMATURE_RETURN_IF_ERROR(IndexParts(asset, asset->contents.skeletons, c->skeletons, "skeleton"));
    ARMATURE_RETURN_IF_ERROR(IndexParts(asset, asset->contents.meshes, c->meshes, "mesh"));
  }
  return c;
}

}  // namespace armature::server
