// The mesh slice's handlers: the work of each unary MeshService RPC over a
// catalog snapshot, callable without gRPC (benchmarks, tests). Every handler of
// every slice takes its inputs in one order: context (catalog or store), limits,
// request, response.
#pragma once

#include "armature/base/status.h"
#include "armature/v1/meshes.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"

namespace armature::server {

Status GetMeshGeometry(const Catalog& catalog, const v1::GetMeshGeometryRequest& request, v1::MeshGeometry* response);
// `limits` bounds a motion's layers and the answer's size.
Status SkinMesh(const Catalog& catalog, const Limits& limits, const v1::SkinMeshRequest& request,
                v1::SkinMeshResponse* response);
// SkinMesh for every mesh of the request's skeleton (Catalog::MeshesOf), posed alike;
// a skeleton without meshes is NOT_FOUND naming it.
Status SkinCharacter(const Catalog& catalog, const Limits& limits, const v1::SkinCharacterRequest& request,
                     v1::SkinCharacterResponse* response);
Status EvaluateBlendshapes(const Catalog& catalog, const v1::EvaluateBlendshapesRequest& request,
                           v1::EvaluateBlendshapesResponse* response);
Status BindMesh(const Catalog& catalog, const v1::BindMeshRequest& request, v1::BindMeshResponse* response);

}  // namespace armature::server
