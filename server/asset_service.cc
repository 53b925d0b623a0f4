#include "server/asset_service.h"

#include "armature/engine/bvh.h"
#include "server/grpc_status.h"
#include "server/import_reactor.h"
#include "server/proto_convert.h"

namespace armature::server {

grpc::ServerReadReactor<v1::ImportAssetRequest>* AssetServiceImpl::ImportAsset(grpc::CallbackServerContext*,
                                                                               v1::ImportAssetResponse* response) {
  return new ImportReactor(store_, limits_, response);
}

grpc::ServerUnaryReactor* AssetServiceImpl::ListAssets(grpc::CallbackServerContext* context,
                                                       const v1::ListAssetsRequest*,
                                                       v1::ListAssetsResponse* response) {
  for (const auto& [name, asset] : store_.Snapshot()->assets) *response->add_assets() = AssetInfoOf(*asset);
  return FinishUnary(context, Status::Ok());
}

grpc::ServerUnaryReactor* AssetServiceImpl::GetAsset(grpc::CallbackServerContext* context,
                                                     const v1::GetAssetRequest* request, v1::AssetInfo* response) {
  const auto catalog = store_.Snapshot();
  auto it = catalog->assets.find(request->name());
  if (it == catalog->assets.end())
    return FinishUnary(context, Status::NotFound("asset '" + request->name() + "' not found"));
  *response = AssetInfoOf(*it->second);
  return FinishUnary(context, Status::Ok());
}

grpc::ServerUnaryReactor* AssetServiceImpl::DeleteAsset(grpc::CallbackServerContext* context,
                                                        const v1::DeleteAssetRequest* request,
                                                        v1::AssetInfo* response) {
  auto deleted = store_.Delete(request->name());
  if (deleted.ok()) *response = AssetInfoOf(**deleted);
  return FinishUnary(context, deleted.status());
}

grpc::ServerUnaryReactor* AssetServiceImpl::ListClips(grpc::CallbackServerContext* context,
                                                      const v1::ListClipsRequest*, v1::ListClipsResponse* response) {
  for (const auto& [name, ref] : store_.Snapshot()->clips)
    *response->add_clips() = ClipInfoOf(*ref.asset, *ref.part, false);
  return FinishUnary(context, Status::Ok());
}

grpc::ServerUnaryReactor* AssetServiceImpl::GetClip(grpc::CallbackServerContext* context,
                                                    const v1::GetClipRequest* request, v1::ClipInfo* response) {
  auto ref = store_.Snapshot()->FindClip(request->clip());
  if (ref.ok()) *response = ClipInfoOf(*ref->asset, *ref->part, true);
  return FinishUnary(context, ref.status());
}

grpc::ServerUnaryReactor* AssetServiceImpl::ListSkeletons(grpc::CallbackServerContext* context,
                                                          const v1::ListSkeletonsRequest*,
                                                          v1::ListSkeletonsResponse* response) {
  for (const auto& [name, ref] : store_.Snapshot()->skeletons)
    *response->add_skeletons() = SkeletonInfoOf(*ref.asset, *ref.part);
  return FinishUnary(context, Status::Ok());
}

grpc::ServerUnaryReactor* AssetServiceImpl::GetSkeleton(grpc::CallbackServerContext* context,
                                                        const v1::GetSkeletonRequest* request,
                                                        v1::Skeleton* response) {
  auto ref = store_.Snapshot()->FindSkeleton(request->skeleton());
  if (ref.ok()) {
    response->set_name(ref->part->name);
    response->set_asset(ref->asset->record.name);
    ToProto(*ref->part->skeleton, response);
  }
  return FinishUnary(context, ref.status());
}

grpc::ServerUnaryReactor* AssetServiceImpl::ExportClip(grpc::CallbackServerContext* context,
                                                       const v1::ExportClipRequest* request,
                                                       v1::ExportClipResponse* response) {
  auto ref = store_.Snapshot()->FindClip(request->clip());
  if (ref.ok()) {
    response->set_filename(ref->part->name + ".bvh");
    response->set_data(WriteBvh(*ref->part->clip));
  }
  return FinishUnary(context, ref.status());
}

}  // namespace armature::server
