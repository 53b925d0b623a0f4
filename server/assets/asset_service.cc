#include "server/assets/asset_service.h"

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "armature/engine/io/bvh.h"
#include "armature/engine/io/gltf_writer.h"
#include "armature/engine/mesh/mesh.h"
#include "server/rpc/call_guard.h"
#include "server/rpc/grpc_status.h"
#include "server/assets/import_reactor.h"
#include "server/assets/asset_convert.h"
#include "server/rpc/convert/pose_convert.h"
#include "server/rpc/request_validation.h"

namespace armature::server {
namespace {

// The writer's own estimate of its output (hierarchy plus frames × channels),
// so a clip whose keys span a huge time is refused before a frame is written.
Status ValidateExportSize(const Clip& clip, const Limits& limits) {
  const std::string how = std::to_string(BvhExportFrameCount(clip)) + " frames of BVH text";
  return ValidateReplySize(static_cast<double>(BvhExportByteEstimate(clip)), limits, "ExportClip", how);
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
  const Skeleton& own = *clip.clip->skeleton;
  std::vector<const Mesh*> same_object;
  std::map<std::string, std::vector<const Mesh*>> same_joints;  // by skeleton name
  for (const auto& [name, ref] : catalog.meshes) {
    if (ref.part->skeleton.empty() || !ref.part->mesh->skinned()) continue;
    auto skeleton = catalog.FindSkeleton(ref.part->skeleton);
    if (!skeleton.ok()) continue;
    const Skeleton& theirs = *skeleton->part->skeleton;
    if (&theirs == &own || ref.part->skeleton == clip.skeleton)
      same_object.push_back(ref.part->mesh.get());
    else if (theirs.names == own.names && theirs.parents == own.parents)
      same_joints[ref.part->skeleton].push_back(ref.part->mesh.get());
  }
  if (!same_object.empty() || same_joints.empty()) return same_object;
  return same_joints.begin()->second;
}

Status ExportGltfClip(const Catalog& catalog, const PartRef<NamedClip>& ref, bool binary, bool with_meshes,
                      const Limits& limits, v1::ExportClipResponse* response) {
  const NamedClip& clip = *ref.part;
  const std::vector<const Mesh*> meshes = with_meshes ? CharacterMeshes(catalog, clip) : std::vector<const Mesh*>{};
  const uint64_t estimate = GltfExportByteEstimate(*clip.clip, meshes, binary);
  ARMATURE_RETURN_IF_ERROR(ValidateReplySize(static_cast<double>(estimate), limits, "ExportClip",
                                             "glTF of " + std::to_string(clip.clip->skeleton->size()) +
                                                 " joints and " + std::to_string(meshes.size()) + " meshes"));
  GltfExportOptions options;
  options.binary = binary;
  // The animation's own name: "robot.Walking" of asset "robot" is "Walking".
  const std::string prefix = ref.asset->record.name + ".";
  options.animation_name = clip.name.rfind(prefix, 0) == 0 ? clip.name.substr(prefix.size()) : clip.name;
  options.max_bytes = static_cast<uint64_t>(limits.max_message_bytes);
  auto bytes = ExportGltf(*clip.clip, meshes, options);
  if (!bytes.ok()) return bytes.status();
  response->set_filename(clip.name + std::string(FormatExtension(binary ? AssetFormat::kGlb : AssetFormat::kGltf)));
  response->set_data(std::move(*bytes));
  return Status::Ok();
}

}  // namespace

grpc::ServerReadReactor<v1::ImportAssetRequest>* AssetServiceImpl::ImportAsset(grpc::CallbackServerContext* context,
                                                                               v1::ImportAssetResponse* response) {
  return MakeReactor<grpc::ServerReadReactor<v1::ImportAssetRequest>>(
      context, "ImportAsset", [&] { return new ImportReactor(context, store_, limits_, uploads_.Admit(), response); });
}

grpc::ServerUnaryReactor* AssetServiceImpl::ListAssets(grpc::CallbackServerContext* context,
                                                       const v1::ListAssetsRequest*,
                                                       v1::ListAssetsResponse* response) {
  return RunUnary(context, "ListAssets", [&]() -> Status {
    // The snapshot is held for the whole loop: a temporary's member would die
    // before the first iteration, and a concurrent import/delete free it.
    const auto catalog = store_.Snapshot();
    for (const auto& [name, asset] : catalog->assets) *response->add_assets() = AssetInfoOf(*asset);
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* AssetServiceImpl::GetAsset(grpc::CallbackServerContext* context,
                                                     const v1::GetAssetRequest* request, v1::AssetInfo* response) {
  return RunUnary(context, "GetAsset", [&]() -> Status {
    const auto catalog = store_.Snapshot();
    auto it = catalog->assets.find(request->name());
    if (it == catalog->assets.end())
      return Status::NotFound("asset '" + request->name() + "' not found");
    *response = AssetInfoOf(*it->second);
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* AssetServiceImpl::DeleteAsset(grpc::CallbackServerContext* context,
                                                        const v1::DeleteAssetRequest* request,
                                                        v1::AssetInfo* response) {
  return RunUnary(context, "DeleteAsset", [&]() -> Status {
    auto deleted = store_.Delete(request->name());
    if (deleted.ok()) *response = AssetInfoOf(**deleted);
    return deleted.status();
  });
}

grpc::ServerUnaryReactor* AssetServiceImpl::ListClips(grpc::CallbackServerContext* context,
                                                      const v1::ListClipsRequest*, v1::ListClipsResponse* response) {
  return RunUnary(context, "ListClips", [&]() -> Status {
    const auto catalog = store_.Snapshot();  // held for the loop (see ListAssets)
    for (const auto& [name, ref] : catalog->clips)
      *response->add_clips() = ClipInfoOf(*ref.asset, *ref.part, false);
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* AssetServiceImpl::GetClip(grpc::CallbackServerContext* context,
                                                    const v1::GetClipRequest* request, v1::ClipInfo* response) {
  return RunUnary(context, "GetClip", [&]() -> Status {
    auto ref = store_.Snapshot()->FindClip(request->clip());
    if (ref.ok()) *response = ClipInfoOf(*ref->asset, *ref->part, true);
    return ref.status();
  });
}

grpc::ServerUnaryReactor* AssetServiceImpl::ListSkeletons(grpc::CallbackServerContext* context,
                                                          const v1::ListSkeletonsRequest*,
                                                          v1::ListSkeletonsResponse* response) {
  return RunUnary(context, "ListSkeletons", [&]() -> Status {
    const auto catalog = store_.Snapshot();  // held for the loop (see ListAssets)
    for (const auto& [name, ref] : catalog->skeletons)
      *response->add_skeletons() = SkeletonInfoOf(*ref.asset, *ref.part);
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* AssetServiceImpl::GetSkeleton(grpc::CallbackServerContext* context,
                                                        const v1::GetSkeletonRequest* request,
                                                        v1::Skeleton* response) {
  return RunUnary(context, "GetSkeleton", [&]() -> Status {
    auto ref = store_.Snapshot()->FindSkeleton(request->skeleton());
    if (ref.ok()) {
      response->set_name(ref->part->name);
      response->set_asset(ref->asset->record.name);
      ToProto(*ref->part->skeleton, response);
    }
    return ref.status();
  });
}

grpc::ServerUnaryReactor* AssetServiceImpl::ExportClip(grpc::CallbackServerContext* context,
                                                       const v1::ExportClipRequest* request,
                                                       v1::ExportClipResponse* response) {
  return RunUnary(context, "ExportClip", [&]() -> Status {
    auto format = ExportFormat(request->format());
    if (!format.ok()) return format.status();
    const auto catalog = store_.Snapshot();
    auto ref = catalog->FindClip(request->clip());
    if (!ref.ok()) return ref.status();
    if (*format != AssetFormat::kBvh)
      return ExportGltfClip(*catalog, *ref, *format == AssetFormat::kGlb, request->with_meshes(), limits_,
                            response);
    if (request->with_meshes())
      return Status::InvalidArgument("with_meshes: BVH holds no meshes; ask for format glb or gltf");
    ARMATURE_RETURN_IF_ERROR(ValidateExportSize(*ref->part->clip, limits_));
    response->set_filename(ref->part->name + ".bvh");
    auto bvh = ExportBvh(*ref->part->clip);
    if (!bvh.ok()) return bvh.status();
    response->set_data(std::move(*bvh));
    return Status::Ok();
  });
}

}  // namespace armature::server
