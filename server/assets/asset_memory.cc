#include "server/assets/asset_memory.h"

#include <set>

#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/mesh/mesh.h"

namespace armature::server {
namespace {

// Element storage of vectors, summed.
template <class... V>
size_t ElementBytes(const V&... v) {
  return (size_t{0} + ... + (v.size() * sizeof(typename V::value_type)));
}

template <class V>
size_t TrackBytes(const Track<V>& t) {
  return ElementBytes(t.times, t.values, t.in_tangents, t.out_tangents);
}

size_t SkeletonBytes(const Skeleton& s) {
  size_t bytes = sizeof(Skeleton);
  for (const std::string& name : s.names) bytes += sizeof(std::string) + name.size();
  for (const auto& c : s.channels) bytes += sizeof(c) + ElementBytes(c);
  bytes += ElementBytes(s.parents, s.rest, s.end_sites);
  return bytes;
}

size_t ClipBytes(const Clip& c) {
  size_t bytes = sizeof(Clip);
  for (const JointTrack& j : c.joints)
    bytes += sizeof(JointTrack) + TrackBytes(j.translation) + TrackBytes(j.rotation) + TrackBytes(j.scale);
  for (const WeightsTrack& w : c.weights)
    bytes += sizeof(WeightsTrack) + w.mesh.size() + ElementBytes(w.times, w.values);
  return bytes;
}

size_t MeshBytes(const Mesh& m) {
  size_t bytes = sizeof(Mesh) + m.name.size();  // sizeof(Mesh) covers the layout's own struct
  bytes += ElementBytes(m.positions, m.normals, m.triangles, m.uvs, m.materials, m.material_groups);
  bytes += ElementBytes(m.joints, m.inverse_bind, m.influence_offsets, m.influence_joints, m.influence_weights);
  for (const MorphTarget& t : m.targets)
    bytes += sizeof(MorphTarget) + t.name.size() + ElementBytes(t.vertices, t.position_deltas, t.normal_deltas);
  bytes += ElementBytes(m.default_weights);
  const SkinningLayout& l = m.layout;
  bytes +=
      ElementBytes(l.order, l.x, l.y, l.z, l.nx, l.ny, l.nz, l.groups, l.joints, l.weights, l.pair_offsets, l.pairs);
  for (const SkinningLayout::Target& t : l.targets)
    bytes += sizeof(SkinningLayout::Target) + ElementBytes(t.vertices, t.dx, t.dy, t.dz, t.nx, t.ny, t.nz);
  return bytes;
}

// Materials and their images (stored bytes), each counted once however
// many meshes share it.
size_t MaterialBytes(const std::set<const Mesh*>& meshes) {
  std::set<const Material*> materials;
  std::set<const MaterialImage*> images;
  size_t bytes = 0;
  for (const Mesh* m : meshes)
    if (m != nullptr)
      for (const auto& material : m->materials)
        if (material && materials.insert(material.get()).second) {
          bytes += sizeof(Material) + material->name.size() + ElementBytes(material->images);
          for (const auto& image : material->images)
            if (image && images.insert(image.get()).second)
              bytes += sizeof(MaterialImage) + image->name.size() + image->mime_type.size() + image->bytes.size();
        }
  return bytes;
}

}  // namespace

size_t EstimateAssetBytes(const AssetContents& contents) {
  std::set<const Skeleton*> skeletons;
  for (const NamedSkeleton& s : contents.skeletons) skeletons.insert(s.skeleton.get());
  size_t bytes = 0;
  for (const NamedClip& c : contents.clips) {
    // The runtime form, and the file form while an asset holds it (an exact runtime form's keys are the file form).
    if (c.clip) {
      skeletons.insert(c.clip->skeleton.get());
      bytes += ClipBytes(*c.clip);
    }
    if (c.runtime) {
      skeletons.insert(c.runtime->skeleton.get());
      bytes += sizeof(CompressedClip) + c.runtime->animated_parts.size();
      if (!c.runtime->exact() || c.runtime->exact_keys != c.clip)
        bytes += c.runtime->exact() ? ClipBytes(*c.runtime->exact_keys) : c.runtime->ByteSize();
    }
  }
  for (const Skeleton* s : skeletons)
    if (s != nullptr) bytes += SkeletonBytes(*s);
  std::set<const Mesh*> meshes;
  for (const NamedMesh& m : contents.meshes) meshes.insert(m.mesh.get());
  for (const Mesh* m : meshes)
    if (m != nullptr) bytes += MeshBytes(*m);
  return bytes + MaterialBytes(meshes);
}

size_t HeldAssetBytes(const Catalog& catalog, const StoredAsset* except) {
  size_t bytes = 0;
  for (const auto& [name, asset] : catalog.assets)
    if (asset.get() != except) bytes += EstimateAssetBytes(asset->contents);
  return bytes;
}

void CollectAssetMetrics(const Catalog& catalog, PrometheusText& out) {
  out.Family("armature_assets_loaded", "gauge", "Loaded assets (imported files) and the parts they provide.");
  out.Sample("armature_assets_loaded", {{"kind", "asset"}}, static_cast<double>(catalog.assets.size()));
  out.Sample("armature_assets_loaded", {{"kind", "skeleton"}}, static_cast<double>(catalog.skeletons.size()));
  out.Sample("armature_assets_loaded", {{"kind", "clip"}}, static_cast<double>(catalog.clips.size()));
  out.Sample("armature_assets_loaded", {{"kind", "mesh"}}, static_cast<double>(catalog.meshes.size()));
  const auto memory = static_cast<double>(HeldAssetBytes(catalog));
  double source = 0;
  for (const auto& [name, asset] : catalog.assets) source += static_cast<double>(asset->record.size_bytes);
  out.Family("armature_assets_memory_bytes", "gauge",
             "Estimated memory of the parsed assets: skeletons, clip tracks and meshes.");
  out.Sample("armature_assets_memory_bytes", {}, memory);
  out.Family("armature_assets_source_bytes", "gauge", "Size of the imported files as stored in the data dir.");
  out.Sample("armature_assets_source_bytes", {}, source);
}

}  // namespace armature::server
