#include "server/authoring/derived_clip.h"

#include <utility>

#include "armature/engine/io/gltf/gltf_writer.h"

namespace armature::server {

StatusOr<DerivedClip> StoreDerivedClip(AssetStore& store, const Clip& clip, const DerivedClipOptions& options,
                                       const Limits& limits) {
  ARMATURE_RETURN_IF_ERROR(ValidateAssetName(options.asset_name));
  GltfExportOptions gltf;
  gltf.binary = true;
  gltf.animation_name = options.asset_name;
  gltf.max_bytes = static_cast<uint64_t>(limits.max_upload_bytes);
  auto bytes = ExportGltf(clip, {}, gltf);
  if (!bytes.ok()) {
    if (bytes.status().code() == StatusCode::kResourceExhausted) {
      return Status::ResourceExhausted(
          "the new clip '" + options.asset_name + "' would be a file over --max-upload-mb (" +
          std::to_string(limits.max_upload_bytes >> 20) + " MB): " + bytes.status().message());
    }
    return bytes.status();
  }
  ImportRequest request;
  request.name = options.asset_name;
  request.filename = options.asset_name + ".glb";
  request.format = "glb";
  request.replace = options.replace;
  request.replace_only = options.replace_only;
  request.bytes = std::move(*bytes);
  request.animates = options.skeleton;
  request.precision = options.precision;
  auto stored = store.Import(std::move(request));
  if (!stored.ok()) return stored.status();
  DerivedClip result{*stored, nullptr};
  const std::string clip_name =
      options.skeleton.empty() ? options.asset_name + "." + options.asset_name : options.asset_name;
  for (const NamedClip& named : result.asset->contents.clips) {
    if (named.name == clip_name) result.clip = &named;
  }
  if (result.clip == nullptr)
    return Status::Internal("stored asset '" + options.asset_name + "' has no clip '" + clip_name + "'");
  return result;
}

}  // namespace armature::server
