// AssetService: thin callback handlers over the AssetStore.
#pragma once

#include "armature/v1/assets.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/assets/upload/upload_admission.h"
#include "server/rpc/limits.h"

namespace armature::server {

class AssetServiceImpl final : public v1::AssetService::CallbackService {
 public:
  AssetServiceImpl(AssetStore& store, const Limits& limits)
      : store_(store), limits_(limits), uploads_(limits.max_concurrent_uploads) {}

  grpc::ServerReadReactor<v1::ImportAssetRequest>* ImportAsset(grpc::CallbackServerContext* context,
                                                               v1::ImportAssetResponse* response) override;
  grpc::ServerUnaryReactor* ListAssets(grpc::CallbackServerContext* context, const v1::ListAssetsRequest* request,
                                       v1::ListAssetsResponse* response) override;
  grpc::ServerUnaryReactor* GetAsset(grpc::CallbackServerContext* context, const v1::GetAssetRequest* request,
                                     v1::AssetInfo* response) override;
  grpc::ServerUnaryReactor* DeleteAsset(grpc::CallbackServerContext* context, const v1::DeleteAssetRequest* request,
                                        v1::AssetInfo* response) override;
  grpc::ServerUnaryReactor* ListClips(grpc::CallbackServerContext* context, const v1::ListClipsRequest* request,
                                      v1::ListClipsResponse* response) override;
  grpc::ServerUnaryReactor* GetClip(grpc::CallbackServerContext* context, const v1::GetClipRequest* request,
                                    v1::ClipInfo* response) override;
  grpc::ServerUnaryReactor* ListSkeletons(grpc::CallbackServerContext* context, const v1::ListSkeletonsRequest* request,
                                          v1::ListSkeletonsResponse* response) override;
  grpc::ServerUnaryReactor* GetSkeleton(grpc::CallbackServerContext* context, const v1::GetSkeletonRequest* request,
                                        v1::Skeleton* response) override;
  grpc::ServerUnaryReactor* ExportClip(grpc::CallbackServerContext* context, const v1::ExportClipRequest* request,
                                       v1::ExportClipResponse* response) override;

 private:
  AssetStore& store_;
  const Limits& limits_;
  UploadAdmission uploads_;
};

}  // namespace armature::server
