#include "server/assets/asset_service.h"

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/gltf/gltf_writer.h"
#include "armature/engine/mesh/mesh.h"
#include "server/rpc/call_guard.h"
#include "server/rpc/grpc_status.h"
#include "server/assets/upload/import_reactor.h"
#include "server/assets/asset_convert.h"
#include "server/assets/clip_export.h"
#include "server/rpc/convert/pose_convert.h"
#include "server/rpc/request_validation.h"

namespace armature::server {

grpc::ServerReadReactor<v1::ImportAssetRequest>* AssetServiceImpl::ImportAsset(grpc::CallbackServerContext* context,
                                                                               v1::ImportAssetResponse* response) {
  return MakeReactor<grpc::ServerReadReactor<v1::ImportAssetRequest>>(
      context, "ImportAsset", [&] { return new ImportReactor(context, store_, limits_, uploads_.Admit(), response); });
}

grpc::ServerUnaryReactor* AssetServiceImpl::ListAssets(grpc::CallbackServerContext* context,
                                                       const v1::ListAssetsRequest*, v1::ListAssetsResponse* response) {
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
    if (it == catalog->assets.end()) return Status::NotFound("asset '" + request->name() + "' not found");
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

grpc::ServerUnaryReactor* AssetServiceImpl::ListClips(grpc::CallbackServerContext* context, const v1::ListClipsRequest*,
                                                      v1::ListClipsResponse* response) {
  return RunUnary(context, "ListClips", [&]() -> Status {
    const auto catalog = store_.Snapshot();  // held for the loop (see ListAssets)
    for (const auto& [name, ref] : catalog->clips) *response->add_clips() = ClipInfoOf(*ref.asset, *ref.part, false);
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
                                                        const v1::GetSkeletonRequest* request, v1::Skeleton* response) {
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
    return server::ExportClip(*store_.Snapshot(), limits_, *request, response, ReplyEncodingOf(*context));
  });
}

}  // namespace armature::server
