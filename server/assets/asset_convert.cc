#include "server/assets/asset_convert.h"

#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/mesh/mesh.h"
#include "server/rpc/convert/pose_convert.h"

namespace armature::server {

v1::SkeletonInfo SkeletonInfoOf(const StoredAsset& asset, const NamedSkeleton& s) {
  v1::SkeletonInfo info;
  info.set_name(s.name);
  info.set_asset(asset.record.name);
  info.set_joint_count(static_cast<int32_t>(s.skeleton->size()));
  return info;
}

v1::ClipInfo ClipInfoOf(const StoredAsset& asset, const NamedClip& c, bool with_joints) {
  v1::ClipInfo info;
  info.set_name(c.name);
  info.set_skeleton(c.skeleton_name);
  info.set_asset(asset.record.name);
  const CompressedClip* runtime = c.runtime.get();
  if (!runtime) return info;
  info.set_duration(runtime->duration);
  info.set_frames(static_cast<int32_t>(runtime->source_frame_count));
  info.set_frame_time(runtime->source_frame_time);
  info.set_interpolation(ToProto(runtime->source_interpolation));
  if (with_joints && runtime->skeleton)
    for (const std::string& name : runtime->skeleton->names) info.add_joints(name);
  {
    info.set_runtime_bytes(static_cast<int64_t>(runtime->ByteSize()));
    info.set_bytes_per_joint_sample(runtime->BytesPerJointSample());
    info.set_exact(runtime->exact());
    if (!runtime->exact()) {
      // Errors are in the skeleton's units; the shell distance is 3 cm in them.
      const double units_per_cm = runtime->bound.shell_distance / ClipPrecision::kShellCentimetres;
      info.set_error_bound_cm(runtime->precision.centimetres);
      info.set_worst_error_cm(runtime->error.worst / units_per_cm);
      info.set_p99_error_cm(runtime->error.p99 / units_per_cm);
    }
  }
  return info;
}

v1::AssetInfo AssetInfoOf(const StoredAsset& asset) {
  v1::AssetInfo info;
  const AssetRecord& r = asset.record;
  info.set_name(r.name);
  info.set_format(std::string(FormatName(r.format)));
  info.set_filename(r.filename);
  info.set_size_bytes(r.size_bytes);
  info.set_imported_at(r.imported_at);
  info.set_version(r.version);
  for (const auto& s : asset.contents.skeletons) *info.add_skeletons() = SkeletonInfoOf(asset, s);
  for (const auto& c : asset.contents.clips) *info.add_clips() = ClipInfoOf(asset, c, false);
  for (const auto& m : asset.contents.meshes) *info.add_meshes() = MeshInfoOf(asset, m);
  return info;
}

v1::MeshInfo MeshInfoOf(const StoredAsset& asset, const NamedMesh& m) {
  v1::MeshInfo info;
  info.set_name(m.name);
  info.set_asset(asset.record.name);
  info.set_skeleton(m.skeleton_name);
  if (m.mesh) {
    info.set_vertex_count(static_cast<int32_t>(m.mesh->vertex_count()));
    info.set_triangle_count(static_cast<int32_t>(m.mesh->triangle_count()));
    info.set_max_influences(static_cast<int32_t>(m.mesh->max_influences()));
    for (const auto& t : m.mesh->targets) info.add_target_names(t.name);
  }
  return info;
}

}  // namespace armature::server
