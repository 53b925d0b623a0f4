// ExportClip's work: a stored clip written as BVH, glTF or GLB (with its
// character's meshes on request), its size bounded before the work in the
// encoding the answer travels in.
#include "server/assets/clip_export.h"

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "armature/engine/anim/compression/clip_keys.h"
#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/gltf/gltf_writer.h"
#include "armature/engine/mesh/mesh.h"
#include "server/rpc/request_validation.h"

namespace armature::server {
namespace {

// The writer's own estimate of its output (hierarchy plus frames × channels),
// so a clip whose keys span a huge time is refused before a frame is written.
// In JSON the file travels as base64: 4 bytes for every 3.
Status ValidateExportSize(double file_bytes, std::string how, ReplyEncoding encoding, const Limits& limits) {
  if (encoding == ReplyEncoding::kJson) how += ", base64 in JSON";
  const double bytes = encoding == ReplyEncoding::kJson ? file_bytes * 4 / 3 : file_bytes;
  return ValidateReplySize(bytes, limits, "ExportClip", how);
}

// The largest file whose answer fits the message limit in `encoding`.
uint64_t MaxFileBytes(ReplyEncoding encoding, const Limits& limits) {
  const auto limit = static_cast<uint64_t>(limits.max_message_bytes);
  return encoding == ReplyEncoding::kJson ? limit / 4 * 3 : limit;
}

StatusOr<AssetFormat> ExportFormat(const std::string& format) {
  if (format.empty() || format == "bvh") return AssetFormat::kBvh;
  if (format == "glb") return AssetFormat::kGlb;
  if (format == "gltf") return AssetFormat::kGltf;
  return Status::InvalidArgument("format: unknown export format '" + format + "'; allowed: bvh, glb, gltf");
}

// The meshes of the clip's character: every mesh skinned to its skeleton (or
// to the one it animates by name: a retargeted or authored clip), else (such
// a clip stored before it was made the skeleton's own, with a copy of the
// character's skeleton) the meshes of the first skeleton, by name, with the
// same joint names in the same order.
std::vector<const Mesh*> CharacterMeshes(const Catalog& catalog, const NamedClip& clip) {
  const Skeleton& own = *clip.runtime->skeleton;
  std::vector<const Mesh*> same_object;
  std::map<std::string, std::vector<const Mesh*>> same_joints;  // by skeleton name
  for (const auto& [name, ref] : catalog.meshes) {
    if (ref.part->skeleton_name.empty() || !ref.part->mesh->skinned()) continue;
    auto skeleton = catalog.FindSkeleton(ref.part->skeleton_name);
    if (!skeleton.ok()) continue;
    const Skeleton& theirs = *skeleton->part->skeleton;
    if (&theirs == &own || ref.part->skeleton_name == clip.skeleton_name)
      same_object.push_back(ref.part->mesh.get());
    else if (theirs.names == own.names && theirs.parents == own.parents)
      same_joints[ref.part->skeleton_name].push_back(ref.part->mesh.get());
  }
  if (!same_object.empty() || same_joints.empty()) return same_object;
  return same_joints.begin()->second;
}

Status ExportGltfClip(const Catalog& catalog, const Limits& limits, const PartRef<NamedClip>& ref, bool binary,
                      bool with_meshes, ReplyEncoding encoding, v1::ExportClipResponse* response) {
  const NamedClip& clip = *ref.part;
  // The runtime form's keys: the stored ones of an exact clip, else its samples at its frames.
  ARMATURE_ASSIGN_OR_RETURN(const std::shared_ptr<const Clip> keys, ClipKeysOf(*clip.runtime));
  const std::vector<const Mesh*> meshes = with_meshes ? CharacterMeshes(catalog, clip) : std::vector<const Mesh*>{};
  const uint64_t estimate = GltfExportByteEstimate(*keys, meshes, binary);
  ARMATURE_RETURN_IF_ERROR(ValidateExportSize(
      static_cast<double>(estimate),
      "glTF of " + std::to_string(keys->skeleton->size()) + " joints and " + std::to_string(meshes.size()) + " meshes",
      encoding, limits));
  GltfExportOptions options;
  options.binary = binary;
  // The animation's own name: "robot.Walking" of asset "robot" is "Walking".
  const std::string prefix = ref.asset->record.name + ".";
  options.animation_name = clip.name.rfind(prefix, 0) == 0 ? clip.name.substr(prefix.size()) : clip.name;
  options.max_bytes = MaxFileBytes(encoding, limits);
  ARMATURE_ASSIGN_OR_RETURN(auto bytes, ExportGltf(*keys, meshes, options));
  response->set_filename(clip.name + std::string(FormatExtension(binary ? AssetFormat::kGlb : AssetFormat::kGltf)));
  response->set_data(std::move(bytes));
  return Status::Ok();
}

}  // namespace

Status ExportClip(const Catalog& catalog, const Limits& limits, const v1::ExportClipRequest& request,
                  v1::ExportClipResponse* response, ReplyEncoding encoding) {
  ARMATURE_ASSIGN_OR_RETURN(const AssetFormat format, ExportFormat(request.format()));
  ARMATURE_ASSIGN_OR_RETURN(auto ref, catalog.FindClip(request.clip()));
  if (format != AssetFormat::kBvh)
    return ExportGltfClip(catalog, limits, ref, format == AssetFormat::kGlb, request.with_meshes(), encoding, response);
  if (request.with_meshes())
    return Status::InvalidArgument("with_meshes: BVH holds no meshes; ask for format glb or gltf");
  ARMATURE_ASSIGN_OR_RETURN(const std::shared_ptr<const Clip> keys, ClipKeysOf(*ref.part->runtime));
  const Clip& clip = *keys;
  ARMATURE_RETURN_IF_ERROR(ValidateExportSize(static_cast<double>(BvhExportByteEstimate(clip)),
                                              std::to_string(BvhExportFrameCount(clip)) + " frames of BVH text",
                                              encoding, limits));
  response->set_filename(ref.part->name + ".bvh");
  ARMATURE_ASSIGN_OR_RETURN(auto bvh, ExportBvh(clip));
  response->set_data(std::move(bvh));
  return Status::Ok();
}

}  // namespace armature::server
