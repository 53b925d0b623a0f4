#include "server/asset_memory.h"

#include <set>

namespace armature::server {
namespace {

template <class V>
size_t TrackBytes(const Track<V>& t) {
  return t.times.size() * sizeof(double) + (t.values.size() + t.in_tangents.size() + t.out_tangents.size()) * sizeof(V);
}

size_t SkeletonBytes(const Skeleton& s) {
  size_t bytes = sizeof(Skeleton);
  for (const std::string& name : s.names) bytes += sizeof(std::string) + name.size();
  bytes += s.parents.size() * sizeof(int) + s.rest.size() * sizeof(Trs);
  for (const auto& c : s.channels) bytes += sizeof(c) + c.size() * sizeof(Channel);
  bytes += s.end_sites.size() * sizeof(std::optional<Eigen::Vector3d>);
  return bytes;
}

size_t ClipBytes(const Clip& c) {
  size_t bytes = sizeof(Clip);
  for (const JointTrack& j : c.joints)
    bytes += sizeof(JointTrack) + TrackBytes(j.translation) + TrackBytes(j.rotation) + TrackBytes(j.scale);
  for (const WeightsTrack& w : c.weights)
    bytes += sizeof(WeightsTrack) + w.mesh.size() + (w.times.size() + w.values.size()) * sizeof(double);
  return bytes;
}

}  // namespace

size_t EstimateAssetBytes(const AssetContents& contents) {
  std::set<const Skeleton*> skeletons;
  for (const NamedSkeleton& s : contents.skeletons) skeletons.insert(s.skeleton.get());
  size_t bytes = 0;
  for (const NamedClip& c : contents.clips) {
    skeletons.insert(c.clip->skeleton.get());
    bytes += ClipBytes(*c.clip);
  }
  for (const Skeleton* s : skeletons)
    if (s != nullptr) bytes += SkeletonBytes(*s);
  return bytes;
}

void CollectAssetMetrics(const Catalog& catalog, PrometheusText& out) {
  out.Family("armature_assets_loaded", "gauge", "Loaded assets (imported files) and the parts they provide.");
  out.Sample("armature_assets_loaded", {{"kind", "asset"}}, static_cast<double>(catalog.assets.size()));
  out.Sample("armature_assets_loaded", {{"kind", "skeleton"}}, static_cast<double>(catalog.skeletons.size()));
  out.Sample("armature_assets_loaded", {{"kind", "clip"}}, static_cast<double>(catalog.clips.size()));
  out.Sample("armature_assets_loaded", {{"kind", "mesh"}}, static_cast<double>(catalog.meshes.size()));
  double memory = 0, source = 0;
  for (const auto& [name, asset] : catalog.assets) {
    memory += static_cast<double>(EstimateAssetBytes(asset->contents));
    source += static_cast<double>(asset->record.size_bytes);
  }
  out.Family("armature_assets_memory_bytes", "gauge",
             "Estimated memory of the parsed assets: skeletons and clip tracks (meshes not counted yet).");
  out.Sample("armature_assets_memory_bytes", {}, memory);
  out.Family("armature_assets_source_bytes", "gauge", "Size of the imported files as stored in the data dir.");
  out.Sample("armature_assets_source_bytes", {}, source);
}

}  // namespace armature::server
