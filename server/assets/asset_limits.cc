#include "server/assets/asset_limits.h"

#include <algorithm>
#include <string>
#include <string_view>
#include <utility>

#include "armature/engine/mesh/mesh.h"

namespace armature::server {

Status CheckAssetLimits(const AssetContents& contents, const Limits& limits) {
  for (const NamedClip& c : contents.clips) {
    // The source's frame count, or the most keys of any track if that is more.
    size_t keys = c.clip->frame_count;
    for (const JointTrack& j : c.clip->joints)
      keys = std::max({keys, j.translation.times.size(), j.rotation.times.size(), j.scale.times.size()});
    for (const WeightsTrack& w : c.clip->weights) keys = std::max(keys, w.times.size());
    const auto frames = static_cast<int64_t>(keys);
    if (frames > limits.max_clip_frames)
      return Status::ResourceExhausted("clip '" + c.name + "' has " + std::to_string(frames) +
                                       " frames, over the limit of " + std::to_string(limits.max_clip_frames) +
                                       " (--max-clip-frames)");
  }
  for (const NamedMesh& m : contents.meshes) {
    const auto vertices = static_cast<int64_t>(m.mesh->vertex_count());
    if (vertices > limits.max_mesh_vertices)
      return Status::ResourceExhausted("mesh '" + m.name + "' has " + std::to_string(vertices) +
                                       " vertices, over the limit of " + std::to_string(limits.max_mesh_vertices) +
                                       " (--max-mesh-vertices)");
  }
  return Status::Ok();
}

ImportLimits ImportLimitsOf(const Limits& limits) {
  ImportLimits caps;
  caps.max_clip_frames = static_cast<uint64_t>(std::max<int64_t>(limits.max_clip_frames, 0));
  caps.max_mesh_vertices = static_cast<uint64_t>(std::max<int64_t>(limits.max_mesh_vertices, 0));
  caps.max_decoded_bytes = static_cast<uint64_t>(std::max<int64_t>(limits.max_assets_bytes, 0));
  caps.max_image_bytes = static_cast<uint64_t>(std::max<int64_t>(limits.max_image_bytes, 0));
  return caps;
}

ImportLimits ImportLimitsWithRoom(const Limits& limits, size_t held_bytes) {
  ImportLimits caps = ImportLimitsOf(limits);
  caps.max_decoded_bytes -= std::min<uint64_t>(caps.max_decoded_bytes, held_bytes);
  return caps;
}

Status CheckAssetsTotal(size_t adding_bytes, size_t held_bytes, const Limits& limits) {
  const uint64_t total = static_cast<uint64_t>(adding_bytes) + held_bytes;
  if (total <= static_cast<uint64_t>(limits.max_assets_bytes)) return Status::Ok();
  auto mib = [](uint64_t bytes) { return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB"; };
  return Status::ResourceExhausted("it takes about " + mib(adding_bytes) + " in memory and the server holds " +
                                   mib(held_bytes) + " of assets: over the limit of " +
                                   mib(static_cast<uint64_t>(limits.max_assets_bytes)) +
                                   " (--max-assets-mb); delete assets or raise the limit");
}

ImportLimits LoadLimitsOf(const Limits& limits) {
  const ImportLimits flags = ImportLimitsOf(limits);
  ImportLimits caps;
  caps.max_clip_frames = std::max(caps.max_clip_frames, flags.max_clip_frames);
  caps.max_mesh_vertices = std::max(caps.max_mesh_vertices, flags.max_mesh_vertices);
  caps.max_decoded_bytes = std::max(caps.max_decoded_bytes, flags.max_decoded_bytes);
  caps.max_image_bytes = std::max(caps.max_image_bytes, flags.max_image_bytes);
  return caps;
}

StatusOr<AssetContents> WithLimitFlags(StatusOr<AssetContents> parsed) {
  if (parsed.ok() || parsed.status().code() != StatusCode::kResourceExhausted) return parsed;
  static constexpr std::pair<std::string_view, std::string_view> kFlags[] = {
      {"max_clip_frames", "--max-clip-frames"},
      {"max_mesh_vertices", "--max-mesh-vertices"},
      {"max_image_bytes", "--max-image-mb"},
      {"max_decoded_bytes", "--max-assets-mb, less what the server holds"}};
  const std::string message = parsed.status().message();
  for (const auto& [field, flag] : kFlags)
    if (message.find(field) != std::string::npos)
      return Status::ResourceExhausted(message + " (" + std::string(flag) + ")");
  return parsed;
}

}  // namespace armature::server
