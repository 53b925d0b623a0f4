// MeshService: mesh details, skinning (one pose or a real-time stream),
// blendshapes and automatic skin weights.
#pragma once

#include <memory>

#include "armature/v1/meshes.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/mesh/mesh_handlers.h"
#include "server/rpc/streams/frame_scheduler.h"
#include "server/rpc/limits.h"
#include "server/rpc/streams/stream_admission.h"

namespace armature::server {

class MeshServiceImpl final : public v1::MeshService::CallbackService {
 public:
  MeshServiceImpl(AssetStore& store, const Limits& limits, std::shared_ptr<StreamAdmission> streams)
      : store_(store), limits_(limits), streams_(std::move(streams)) {}

  grpc::ServerUnaryReactor* ListMeshes(grpc::CallbackServerContext* context, const v1::ListMeshesRequest* request,
                                       v1::ListMeshesResponse* response) override;
  grpc::ServerUnaryReactor* GetMesh(grpc::CallbackServerContext* context, const v1::GetMeshRequest* request,
                                    v1::MeshInfo* response) override;
  grpc::ServerUnaryReactor* GetMeshGeometry(grpc::CallbackServerContext* context,
                                            const v1::GetMeshGeometryRequest* request,
                                            v1::MeshGeometry* response) override;
  grpc::ServerUnaryReactor* GetMaterial(grpc::CallbackServerContext* context, const v1::GetMaterialRequest* request,
                                        v1::Material* response) override;
  grpc::ServerUnaryReactor* GetMaterialImage(grpc::CallbackServerContext* context,
                                             const v1::GetMaterialImageRequest* request,
                                             v1::MaterialImage* response) override;
  grpc::ServerUnaryReactor* SkinMesh(grpc::CallbackServerContext* context, const v1::SkinMeshRequest* request,
                                     v1::SkinMeshResponse* response) override;
  grpc::ServerUnaryReactor* SkinCharacter(grpc::CallbackServerContext* context, const v1::SkinCharacterRequest* request,
                                          v1::SkinCharacterResponse* response) override;
  grpc::ServerWriteReactor<v1::SkinnedMeshFrame>* StreamSkinnedMesh(
      grpc::CallbackServerContext* context, const v1::StreamSkinnedMeshRequest* request) override;
  grpc::ServerUnaryReactor* EvaluateBlendshapes(grpc::CallbackServerContext* context,
                                                const v1::EvaluateBlendshapesRequest* request,
                                                v1::EvaluateBlendshapesResponse* response) override;
  grpc::ServerUnaryReactor* BindMesh(grpc::CallbackServerContext* context, const v1::BindMeshRequest* request,
                                     v1::BindMeshResponse* response) override;

 private:
  AssetStore& store_;
  const Limits& limits_;
  std::shared_ptr<StreamAdmission> streams_;  // shared with the other streaming RPCs
  FrameScheduler scheduler_;                  // paces StreamSkinnedMesh
};

}  // namespace armature::server
