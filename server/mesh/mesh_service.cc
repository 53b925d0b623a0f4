#include "server/mesh/mesh_service.h"

#include <google/protobuf/io/coded_stream.h>
#include <spdlog/spdlog.h>

#include "armature/engine/mesh/auto_weights.h"
#include "armature/engine/mesh/blendshape.h"
#include "armature/engine/kinematics/fk.h"
#include "armature/engine/mesh/mesh.h"
#include "armature/engine/mesh/skinning.h"
#include "server/rpc/call_guard.h"
#include "server/rpc/grpc_status.h"
#include "server/rpc/paced_stream_reactor.h"
#include "server/rpc/proto_convert.h"
#include "server/rpc/request_validation.h"

namespace armature::server {
namespace {

StatusOr<SkinningMethod> FromProto(v1::SkinningMethod method) {
  switch (method) {
    case v1::SKINNING_METHOD_UNSPECIFIED:
    case v1::LBS: return SkinningMethod::kLinear;
    case v1::DQS: return SkinningMethod::kDualQuaternion;
    default: return Status::InvalidArgument("method: unknown skinning method " + std::to_string(method));
  }
}

// The clip that poses `mesh`: it must animate the mesh's skeleton (any
// clip for an unbound mesh, which only its morph weights track moves).
StatusOr<PartRef<NamedClip>> ClipFor(const Catalog& catalog, const NamedMesh& mesh, const std::string& name) {
  auto clip = catalog.FindClip(name);
  if (!clip.ok()) return clip.status().WithContext("clip: ");
  if (!mesh.skeleton.empty() && clip->part->skeleton != mesh.skeleton)
    return Status::InvalidArgument("clip: '" + name + "' animates skeleton '" + clip->part->skeleton +
                                   "', not the mesh's skeleton '" + mesh.skeleton + "'");
  return clip;
}

// Output arrays sized in the response (its only allocation) and viewed as spans.
template <class Response>
std::pair<std::span<float>, std::span<float>> OutputsOf(const Mesh& mesh, Response* response) {
  const int n = static_cast<int>(mesh.vertex_count());
  response->mutable_positions()->Resize(3 * n, 0.f);
  if (!mesh.normals.empty()) response->mutable_normals()->Resize(3 * n, 0.f);
  return {{response->mutable_positions()->mutable_data(), static_cast<size_t>(response->positions_size())},
          {response->mutable_normals()->mutable_data(), static_cast<size_t>(response->normals_size())}};
}

// The bytes of a reply carrying `mesh`'s positions and normals (3 floats per
// vertex each), and with `triangles` its indices (varints), computed before
// any work so an oversized reply is refused naming the flags instead of
// failing in gRPC after the work.
Status ValidateMeshReply(const Mesh& mesh, bool triangles, const Limits& limits, const std::string& rpc) {
  const double n = static_cast<double>(mesh.vertex_count());
  double bytes = n * 12 * (mesh.normals.empty() ? 1 : 2);
  if (triangles)
    for (uint32_t index : mesh.triangles) bytes += google::protobuf::io::CodedOutputStream::VarintSize32(index);
  const std::string how = std::to_string(mesh.vertex_count()) + " vertices" +
                          (triangles ? " and " + std::to_string(mesh.triangles.size() / 3) + " triangles" : "");
  return ValidateReplySize(bytes, limits, rpc, how + "; imports are capped by --max-mesh-vertices");
}

Status ValidateMeshReply(const Catalog& catalog, const std::string& name, bool triangles, const Limits& limits,
                         const std::string& rpc) {
  auto ref = catalog.FindMesh(name);
  if (!ref.ok()) return Status::Ok();  // the RPC itself reports it
  return ValidateMeshReply(*ref->part->mesh, triangles, limits, rpc);
}

// Per-thread scratch: skinning is allocation-free after a thread's first call.
struct MeshWorkspace {
  SkinningWorkspace skin;
  std::vector<Trs> local;
};

}  // namespace

Status GetMeshGeometry(const Catalog& catalog, const v1::GetMeshGeometryRequest& request,
                       v1::MeshGeometry* response) {
  auto ref = catalog.FindMesh(request.mesh());
  if (!ref.ok()) return ref.status().WithContext("mesh: ");
  const Mesh& mesh = *ref->part->mesh;
  auto copy = [](const std::vector<Eigen::Vector3f>& points, google::protobuf::RepeatedField<float>* out) {
    out->Reserve(static_cast<int>(3 * points.size()));
    for (const Eigen::Vector3f& p : points) out->Add(p.data(), p.data() + 3);
  };
  copy(mesh.positions, response->mutable_positions());
  copy(mesh.normals, response->mutable_normals());
  response->mutable_triangles()->Add(mesh.triangles.begin(), mesh.triangles.end());
  response->set_mesh(ref->part->name);
  response->set_vertex_count(static_cast<int>(mesh.vertex_count()));
  return Status::Ok();
}

Status SkinMesh(const Catalog& catalog, const v1::SkinMeshRequest& request, v1::SkinMeshResponse* response) {
  auto ref = catalog.FindMesh(request.mesh());
  if (!ref.ok()) return ref.status().WithContext("mesh: ");
  const NamedMesh& named = *ref->part;
  const Mesh& mesh = *named.mesh;
  auto method = FromProto(request.method());
  if (!method.ok()) return method.status();
  ARMATURE_RETURN_IF_ERROR(ValidateWeights(AsSpan(request.morph_weights()), mesh.targets.size(), "morph_weights"));
  SkinningOptions options;
  options.method = *method;
  options.morph_weights = AsSpan(request.morph_weights());

  ARMATURE_RETURN_IF_ERROR(ValidateSkinSource(request));
  ARMATURE_RETURN_IF_ERROR(ValidateEnum(request.method(), v1::SkinningMethod_descriptor(), "method"));
  ARMATURE_RETURN_IF_ERROR(ValidateEnum(request.interpolation(), v1::Interpolation_descriptor(), "interpolation"));
  ARMATURE_RETURN_IF_ERROR(ValidateEnum(request.wrap(), v1::WrapMode_descriptor(), "wrap"));
  thread_local MeshWorkspace ws;
  if (!request.clip().empty()) {
    auto clip = ClipFor(catalog, named, request.clip());
    if (!clip.ok()) return clip.status();
    ARMATURE_RETURN_IF_ERROR(ValidateClipTime(request.time(), "time"));
    SampleOptions sample;
    sample.interpolation = server::FromProto(request.interpolation());
    sample.wrap = server::FromProto(request.wrap());
    auto [positions, normals] = OutputsOf(mesh, response);
    ARMATURE_RETURN_IF_ERROR(
        SkinClip(mesh, *clip->part->clip, request.time(), sample, options, positions, normals, ws.skin));
  } else {
    if (named.skeleton.empty())
      return Status::InvalidArgument("pose: mesh '" + named.name + "' has no skeleton to pose; give a clip");
    auto skeleton_ref = catalog.FindSkeleton(named.skeleton);
    if (!skeleton_ref.ok()) return skeleton_ref.status();
    const Skeleton& skeleton = *skeleton_ref->part->skeleton;
    ws.local.resize(skeleton.size());
    ARMATURE_RETURN_IF_ERROR(PoseFromArrays(skeleton, AsSpan(request.pose().rotations()),
                                            AsSpan(request.pose().translations()), ws.local)
                                 .WithContext("pose: "));
    auto [positions, normals] = OutputsOf(mesh, response);
    ARMATURE_RETURN_IF_ERROR(SkinPose(mesh, skeleton, ws.local, options, positions, normals, ws.skin));
  }
  response->set_mesh(named.name);
  response->set_vertex_count(static_cast<int>(mesh.vertex_count()));
  return Status::Ok();
}

Status EvaluateBlendshapes(const Catalog& catalog, const v1::EvaluateBlendshapesRequest& request,
                           v1::EvaluateBlendshapesResponse* response) {
  auto ref = catalog.FindMesh(request.mesh());
  if (!ref.ok()) return ref.status().WithContext("mesh: ");
  const Mesh& mesh = *ref->part->mesh;
  ARMATURE_RETURN_IF_ERROR(ValidateWeights(AsSpan(request.weights()), mesh.targets.size(), "weights"));
  thread_local SkinningWorkspace ws;
  auto [positions, normals] = OutputsOf(mesh, response);
  BlendshapeJob job;
  job.mesh = &mesh;
  job.weights = AsSpan(request.weights());
  job.positions = positions;
  job.normals = normals;
  job.workspace = &ws;
  ARMATURE_RETURN_IF_ERROR(job.Run());
  response->set_mesh(ref->part->name);
  response->set_vertex_count(static_cast<int>(mesh.vertex_count()));
  return Status::Ok();
}

Status BindMesh(const Catalog& catalog, const v1::BindMeshRequest& request, v1::BindMeshResponse* response) {
  auto ref = catalog.FindMesh(request.mesh());
  if (!ref.ok()) return ref.status().WithContext("mesh: ");
  auto skeleton_ref = catalog.FindSkeleton(request.skeleton());
  if (!skeleton_ref.ok()) return skeleton_ref.status().WithContext("skeleton: ");
  BindOptions options;
  switch (request.method()) {
    case v1::WEIGHT_METHOD_UNSPECIFIED:
    case v1::HEAT: options.method = WeightMethod::kHeat; break;
    case v1::DISTANCE: options.method = WeightMethod::kDistance; break;
    default: return Status::InvalidArgument("method: unknown weight method " + std::to_string(request.method()));
  }
  ARMATURE_RETURN_IF_ERROR(ValidateMaxInfluences(request.max_influences()));
  if (request.max_influences() != 0) options.max_influences = request.max_influences();
  auto bound = armature::BindMesh(*ref->part->mesh, *skeleton_ref->part->skeleton, options);
  if (!bound.ok()) return bound.status();
  const Mesh& mesh = bound->mesh;
  response->set_mesh(ref->part->name);
  response->set_skeleton(skeleton_ref->part->name);
  response->mutable_influence_offsets()->Add(mesh.influence_offsets.begin(), mesh.influence_offsets.end());
  response->mutable_influence_joints()->Reserve(static_cast<int>(mesh.influence_joints.size()));
  for (uint32_t k : mesh.influence_joints) response->add_influence_joints(mesh.joints[k]);  // skin → skeleton joint
  response->mutable_influence_weights()->Add(mesh.influence_weights.begin(), mesh.influence_weights.end());
  for (const std::string& w : bound->warnings) response->add_warnings(w);
  response->set_max_influences(static_cast<int>(mesh.max_influences()));
  return Status::Ok();
}

namespace {

// Plays a clip on a mesh: one skinned mesh per frame.
class StreamSkinnedMeshReactor final : public PacedStreamReactor<v1::SkinnedMeshFrame> {
 public:
  StreamSkinnedMeshReactor(FrameScheduler& scheduler, StreamPacing pacing, PartRef<NamedMesh> mesh,
                           PartRef<NamedClip> clip, SkinningMethod method, v1::Interpolation interpolation)
      : PacedStreamReactor(scheduler, pacing, clip.part->clip->duration), mesh_(std::move(mesh)),
        clip_(std::move(clip)), interpolation_(interpolation) {
    options_.method = method;
    Start();
  }

 private:
  Status Fill(uint64_t index, double t, WrapMode wrap, v1::SkinnedMeshFrame& frame) override {
    SampleOptions sample;
    sample.interpolation = server::FromProto(interpolation_);
    sample.wrap = wrap;
    const Mesh& mesh = *mesh_.part->mesh;
    auto [positions, normals] = OutputsOf(mesh, &frame);
    ARMATURE_RETURN_IF_ERROR(SkinClip(mesh, *clip_.part->clip, t, sample, options_, positions, normals, ws_));
    frame.set_index(index);
    frame.set_time(t);
    return Status::Ok();
  }
  void OnStreamDone(uint64_t frames) override {
    spdlog::debug("skinned stream of '{}' by '{}' done after {} frames", mesh_.part->name, clip_.part->name, frames);
  }

  PartRef<NamedMesh> mesh_;
  PartRef<NamedClip> clip_;
  v1::Interpolation interpolation_;
  SkinningOptions options_;
  SkinningWorkspace ws_;
};

}  // namespace

grpc::ServerWriteReactor<v1::SkinnedMeshFrame>* MeshServiceImpl::StreamSkinnedMesh(
    grpc::CallbackServerContext* context, const v1::StreamSkinnedMeshRequest* request) {
  return MakeReactor<grpc::ServerWriteReactor<v1::SkinnedMeshFrame>>(context, "StreamSkinnedMesh", [&]() -> grpc::ServerWriteReactor<v1::SkinnedMeshFrame>* {
    using Failed = FailedStream<v1::SkinnedMeshFrame>;
    auto stream = streams_->Admit(*context, "StreamSkinnedMesh");
    if (!stream.ok()) return new Failed(stream.status());
    auto catalog = store_.Snapshot();
    auto mesh = catalog->FindMesh(request->mesh());
    if (!mesh.ok()) return new Failed(mesh.status().WithContext("mesh: "));
    if (Status st = ValidateMeshReply(*mesh->part->mesh, false, limits_, "StreamSkinnedMesh"); !st.ok())
      return new Failed(st);
    if (Status st = ValidateRequired(request->clip(), "clip"); !st.ok()) return new Failed(st);
    auto clip = ClipFor(*catalog, *mesh->part, request->clip());
    if (!clip.ok()) return new Failed(clip.status());
    auto method = FromProto(request->method());
    if (!method.ok()) return new Failed(method.status());
    StreamPacing pacing = PacingOf(*request);
    if (Status st = ValidatePacing(pacing, limits_); !st.ok()) return new Failed(st);
    auto* reactor = new StreamSkinnedMeshReactor(scheduler_, pacing, std::move(*mesh), std::move(*clip), *method,
                                                 request->interpolation());
    reactor->HoldUntilDone(std::move(*stream));
    return reactor;
  });
}

grpc::ServerUnaryReactor* MeshServiceImpl::ListMeshes(grpc::CallbackServerContext* context,
                                                      const v1::ListMeshesRequest*,
                                                      v1::ListMeshesResponse* response) {
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
    ARMATURE_RETURN_IF_ERROR(ValidateMeshReply(*catalog, request->mesh(), true, limits_, "GetMeshGeometry"));
    return server::GetMeshGeometry(*catalog, *request, response);
  });
}

grpc::ServerUnaryReactor* MeshServiceImpl::SkinMesh(grpc::CallbackServerContext* context,
                                                    const v1::SkinMeshRequest* request,
                                                    v1::SkinMeshResponse* response) {
  return RunUnary(context, "SkinMesh", [&]() -> Status {
    const auto catalog = store_.Snapshot();
    ARMATURE_RETURN_IF_ERROR(ValidateMeshReply(*catalog, request->mesh(), false, limits_, "SkinMesh"));
    return server::SkinMesh(*catalog, *request, response);
  });
}

grpc::ServerUnaryReactor* MeshServiceImpl::EvaluateBlendshapes(grpc::CallbackServerContext* context,
                                                               const v1::EvaluateBlendshapesRequest* request,
                                                               v1::EvaluateBlendshapesResponse* response) {
  return RunUnary(context, "EvaluateBlendshapes", [&]() -> Status {
    const auto catalog = store_.Snapshot();
    ARMATURE_RETURN_IF_ERROR(ValidateMeshReply(*catalog, request->mesh(), false, limits_, "EvaluateBlendshapes"));
    return server::EvaluateBlendshapes(*catalog, *request, response);
  });
}

grpc::ServerUnaryReactor* MeshServiceImpl::BindMesh(grpc::CallbackServerContext* context,
                                                    const v1::BindMeshRequest* request,
                                                    v1::BindMeshResponse* response) {
  return RunUnary(context, "BindMesh", [&]() -> Status {
    return server::BindMesh(*store_.Snapshot(), *request, response);
  });
}

}  // namespace armature::server
