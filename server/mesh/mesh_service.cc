#include "server/mesh/mesh_service.h"

#include "server/assets/asset_convert.h"
#include "server/mesh/material_handlers.h"
#include "server/mesh/mesh_convert.h"
#include "server/mesh/skinned_mesh_stream_plan.h"
#include "server/mesh/skinned_motion_stream_plan.h"
#include "server/rpc/call_guard.h"
#include "server/rpc/grpc_status.h"
#include "server/rpc/request_validation.h"
#include "server/rpc/streams/paced_stream_reactor.h"
#include "server/rpc/work/work_budget.h"

namespace armature::server {

grpc::ServerWriteReactor<v1::SkinnedMeshFrame>* MeshServiceImpl::StreamSkinnedMesh(
    grpc::CallbackServerContext* context, const v1::StreamSkinnedMeshRequest* request) {
  return MakeReactor<grpc::ServerWriteReactor<v1::SkinnedMeshFrame>>(
      context, "StreamSkinnedMesh", [&]() -> grpc::ServerWriteReactor<v1::SkinnedMeshFrame>* {
        using Failed = FailedStream<v1::SkinnedMeshFrame>;
        auto stream = streams_->Admit(*context, "StreamSkinnedMesh");
        if (!stream.ok()) return new Failed(stream.status());
        auto catalog = store_.Snapshot();
        auto mesh = catalog->FindMesh(request->mesh());
        if (!mesh.ok()) return new Failed(mesh.status().WithContext("mesh: "));
        if (Status st =
                ValidateMeshReply(*mesh->part->mesh, false, limits_, "StreamSkinnedMesh", ReplyEncodingOf(*context));
            !st.ok())
          return new Failed(st);
        if (Status st = ValidateClipOrMotion(request->clip(), request->has_motion()); !st.ok()) return new Failed(st);
        auto method = FromProto(request->method());
        if (!method.ok()) return new Failed(method.status());
        StreamPacing pacing = PacingOf(*request);
        if (Status st = ValidatePacing(pacing, limits_); !st.ok()) return new Failed(st);
        if (request->has_motion()) {
          auto plan = MotionFor(*catalog, *mesh->part, request->motion(), limits_);
          if (!plan.ok()) return new Failed(plan.status());
          if (Status st =
                  ValidateStreamWork(static_cast<int64_t>(plan->layers.size()),
                                     static_cast<int64_t>(plan->skeleton->size()), pacing.fps, limits_, "motion");
              !st.ok())
            return new Failed(st);
          return new PacedStreamReactor<SkinnedMotionStreamPlan>(
              scheduler_, pacing, SkinnedMotionStreamPlan(pacing, std::move(*mesh), std::move(*plan), *method),
              std::move(*stream));
        }
        auto mesh_clip = ClipFor(*catalog, *mesh->part, request->clip());
        if (!mesh_clip.ok()) return new Failed(mesh_clip.status());
        return new PacedStreamReactor<SkinnedMeshStreamPlan>(
            scheduler_, pacing,
            SkinnedMeshStreamPlan(std::move(*mesh), std::move(*mesh_clip), *method, request->interpolation()),
            std::move(*stream));
      });
}

grpc::ServerUnaryReactor* MeshServiceImpl::ListMeshes(grpc::CallbackServerContext* context,
                                                      const v1::ListMeshesRequest*, v1::ListMeshesResponse* response) {
  return RunUnary(context, "ListMeshes", [&]() -> Status {
    auto catalog = store_.Snapshot();
    for (const auto& [name, ref] : catalog->meshes) *response->add_meshes() = MeshInfoOf(*ref.asset, *ref.part);
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* MeshServiceImpl::GetMesh(grpc::CallbackServerContext* context,
                                                   const v1::GetMeshRequest* request, v1::MeshInfo* response) {
  return RunUnary(context, "GetMesh", [&]() -> Status {
    auto ref = store_.Snapshot()->FindMesh(request->mesh());
    if (ref.ok()) *response = MeshInfoOf(*ref->asset, *ref->part);
    return ref.ok() ? Status::Ok() : ref.status().WithContext("mesh: ");
  });
}

grpc::ServerUnaryReactor* MeshServiceImpl::GetMeshGeometry(grpc::CallbackServerContext* context,
                                                           const v1::GetMeshGeometryRequest* request,
                                                           v1::MeshGeometry* response) {
  return RunUnary(context, "GetMeshGeometry", [&]() -> Status {
    const auto catalog = store_.Snapshot();
    ARMATURE_RETURN_IF_ERROR(
        ValidateMeshReply(*catalog, request->mesh(), true, limits_, "GetMeshGeometry", ReplyEncodingOf(*context)));
    return server::GetMeshGeometry(*catalog, *request, response);
  });
}

grpc::ServerUnaryReactor* MeshServiceImpl::GetMaterial(grpc::CallbackServerContext* context,
                                                       const v1::GetMaterialRequest* request, v1::Material* response) {
  return RunUnary(context, "GetMaterial",
                  [&]() -> Status { return server::GetMaterial(*store_.Snapshot(), *request, response); });
}

grpc::ServerUnaryReactor* MeshServiceImpl::GetMaterialImage(grpc::CallbackServerContext* context,
                                                            const v1::GetMaterialImageRequest* request,
                                                            v1::MaterialImage* response) {
  return RunUnary(context, "GetMaterialImage", [&]() -> Status {
    return server::GetMaterialImage(*store_.Snapshot(), *request, response, limits_);
  });
}

grpc::ServerUnaryReactor* MeshServiceImpl::SkinMesh(grpc::CallbackServerContext* context,
                                                    const v1::SkinMeshRequest* request,
                                                    v1::SkinMeshResponse* response) {
  return RunUnary(context, "SkinMesh", [&]() -> Status {
    const auto catalog = store_.Snapshot();
    ARMATURE_RETURN_IF_ERROR(
        ValidateMeshReply(*catalog, request->mesh(), false, limits_, "SkinMesh", ReplyEncodingOf(*context)));
    return server::SkinMesh(*catalog, limits_, *request, response);
  });
}

grpc::ServerUnaryReactor* MeshServiceImpl::SkinCharacter(grpc::CallbackServerContext* context,
                                                         const v1::SkinCharacterRequest* request,
                                                         v1::SkinCharacterResponse* response) {
  return RunUnary(context, "SkinCharacter", [&]() -> Status {
    const auto catalog = store_.Snapshot();
    if (auto skeleton = catalog->FindSkeleton(request->skeleton()); skeleton.ok())
      ARMATURE_RETURN_IF_ERROR(ValidateCharacterReply(catalog->MeshesOf(skeleton->part->name), limits_, "SkinCharacter",
                                                      ReplyEncodingOf(*context)));
    return server::SkinCharacter(*catalog, limits_, *request, response);
  });
}

grpc::ServerUnaryReactor* MeshServiceImpl::EvaluateBlendshapes(grpc::CallbackServerContext* context,
                                                               const v1::EvaluateBlendshapesRequest* request,
                                                               v1::EvaluateBlendshapesResponse* response) {
  return RunUnary(context, "EvaluateBlendshapes", [&]() -> Status {
    const auto catalog = store_.Snapshot();
    ARMATURE_RETURN_IF_ERROR(
        ValidateMeshReply(*catalog, request->mesh(), false, limits_, "EvaluateBlendshapes", ReplyEncodingOf(*context)));
    return server::EvaluateBlendshapes(*catalog, *request, response);
  });
}

grpc::ServerUnaryReactor* MeshServiceImpl::BindMesh(grpc::CallbackServerContext* context,
                                                    const v1::BindMeshRequest* request,
                                                    v1::BindMeshResponse* response) {
  return RunUnary(context, "BindMesh",
                  [&]() -> Status { return server::BindMesh(*store_.Snapshot(), *request, response); });
}

}  // namespace armature::server
