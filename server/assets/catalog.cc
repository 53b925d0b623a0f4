#include "server/assets/catalog.h"

#include <utility>

#include "armature/base/closest_name.h"

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

// NOT_FOUND that helps: a close name ("did you mean"), and when `name` is an asset's name, that
// asset's parts of this kind ("mesh 'cesium_man' not found; asset 'cesium_man' has meshes: …").
template <class Part>
StatusOr<PartRef<Part>> FindIn(const Catalog& catalog, const std::map<std::string, PartRef<Part>>& index,
                               std::string_view name, std::string_view kind, std::string_view kinds,
                               const std::vector<Part> AssetContents::*parts_of) {
  auto it = index.find(std::string(name));
  if (it != index.end()) return it->second;
  std::string message = std::string(kind) + " '" + std::string(name) + "' not found";
  if (auto asset = catalog.assets.find(std::string(name)); asset != catalog.assets.end()) {
    std::vector<std::string_view> parts;
    for (const Part& p : asset->second->contents.*parts_of) parts.push_back(p.name);
    message += "; asset '" + asset->first + "' has " +
               (parts.empty() ? "no " + std::string(kinds) : std::string(kinds) + ": " + JoinNames(parts));
    return Status::NotFound(std::move(message));
  }
  std::vector<std::string_view> names;
  names.reserve(index.size());
  for (const auto& [n, ref] : index) names.push_back(n);
  return Status::NotFound(message + DidYouMean(name, names));
}

}  // namespace

StatusOr<PartRef<NamedClip>> Catalog::FindClip(std::string_view name) const {
  return FindIn(*this, clips, name, "clip", "clips", &AssetContents::clips);
}
StatusOr<PartRef<NamedSkeleton>> Catalog::FindSkeleton(std::string_view name) const {
  return FindIn(*this, skeletons, name, "skeleton", "skeletons", &AssetContents::skeletons);
}
StatusOr<PartRef<NamedMesh>> Catalog::FindMesh(std::string_view name) const {
  return FindIn(*this, meshes, name, "mesh", "meshes", &AssetContents::meshes);
}

std::vector<const NamedMesh*> Catalog::MeshesOf(std::string_view skeleton) const {
  std::vector<const NamedMesh*> out;
  for (const auto& [name, ref] : meshes)
    if (!skeleton.empty() && ref.part->skeleton_name == skeleton) out.push_back(ref.part);
  return out;
}

StatusOr<std::shared_ptr<const StoredAsset>> Catalog::FindOwner(std::string_view name) const {
  const std::string key(name);
  if (auto it = assets.find(key); it != assets.end()) return it->second;
  if (auto it = clips.find(key); it != clips.end()) return it->second.asset;
  if (auto it = skeletons.find(key); it != skeletons.end()) return it->second.asset;
  if (auto it = meshes.find(key); it != meshes.end()) return it->second.asset;
  return Status::NotFound("no asset, clip, skeleton or mesh named '" + key + "'");
}

Status AdoptDerivedClip(const AssetRecord& record, AssetContents& contents) {
  if (record.animates.empty()) return Status::Ok();
  if (contents.clips.size() != 1 || !contents.meshes.empty())
    return Status::InvalidArgument("asset '" + record.name + "': a clip made for skeleton '" + record.animates +
                                   "' must hold one clip and no mesh, not " + std::to_string(contents.clips.size()) +
                                   " clips and " + std::to_string(contents.meshes.size()) + " meshes");
  contents.clips[0].name = record.name;
  contents.clips[0].skeleton_name = record.animates;
  contents.skeletons.clear();
  return Status::Ok();
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
