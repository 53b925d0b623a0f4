#include "server/mesh/mesh_handlers.h"

#include "armature/engine/kinematics/fk.h"
#include "armature/engine/mesh/auto_weights.h"
#include "armature/engine/mesh/blendshape.h"
#include "armature/engine/mesh/mesh.h"
#include "armature/engine/mesh/skinning.h"
#include "server/mesh/mesh_convert.h"
#include "server/mesh/mesh_validation.h"
#include "server/rpc/convert/pose_convert.h"
#include "server/rpc/request_validation.h"

namespace armature::server {
namespace {

// Per-thread scratch: skinning is allocation-free after a thread's first call.
struct MeshWorkspace {
  SkinningWorkspace skin;
  std::vector<Trs> local;
  MotionWorkspace motion;
};

}  // namespace

Status GetMeshGeometry(const Catalog& catalog, const v1::GetMeshGeometryRequest& request, v1::MeshGeometry* response) {
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
  response->mutable_uvs()->Reserve(static_cast<int>(2 * mesh.uvs.size()));
  for (const Eigen::Vector2f& uv : mesh.uvs) response->mutable_uvs()->Add(uv.data(), uv.data() + 2);
  for (const auto& material : mesh.materials) response->add_materials(material->name);
  for (const MaterialGroup& g : mesh.material_groups) {
    v1::MaterialGroup* group = response->add_material_groups();
    group->set_first_triangle(g.first_triangle);
    group->set_triangle_count(g.triangle_count);
    group->set_material(g.material);
  }
  response->set_mesh(ref->part->name);
  response->set_vertex_count(static_cast<int>(mesh.vertex_count()));
  return Status::Ok();
}

Status SkinMesh(const Catalog& catalog, const Limits& limits, const v1::SkinMeshRequest& request,
                v1::SkinMeshResponse* response) {
  auto ref = catalog.FindMesh(request.mesh());
  if (!ref.ok()) return ref.status().WithContext("mesh: ");
  const NamedMesh& named = *ref->part;
  const Mesh& mesh = *named.mesh;
  ARMATURE_ASSIGN_OR_RETURN(const SkinningMethod method, FromProto(request.method()));
  ARMATURE_RETURN_IF_ERROR(ValidateWeights(AsSpan(request.morph_weights()), mesh.targets.size(), "morph_weights"));
  SkinningOptions options;
  options.method = method;
  options.morph_weights = AsSpan(request.morph_weights());

  ARMATURE_RETURN_IF_ERROR(ValidateSkinSource(request));
  ARMATURE_RETURN_IF_ERROR(ValidateEnum(request.interpolation(), v1::Interpolation_descriptor(), "interpolation"));
  ARMATURE_RETURN_IF_ERROR(ValidateEnum(request.wrap(), v1::WrapMode_descriptor(), "wrap"));
  thread_local MeshWorkspace ws;
  if (request.has_motion()) {
    ARMATURE_RETURN_IF_ERROR(ValidateClipTime(request.time(), "time"));
    ARMATURE_ASSIGN_OR_RETURN(auto plan, MotionFor(catalog, named, request.motion(), limits));
    const Skeleton& skeleton = *plan.skeleton;
    ws.local.resize(skeleton.size());
    ws.motion.Resize(plan);
    ARMATURE_RETURN_IF_ERROR((BlendMotionJob{&plan, request.time(), &ws.motion, ws.local}.Run()));
    auto [positions, normals] = OutputsOf(mesh, response);
    ARMATURE_RETURN_IF_ERROR(SkinPose(mesh, skeleton, ws.local, options, positions, normals, ws.skin));
  } else if (!request.clip().empty()) {
    ARMATURE_ASSIGN_OR_RETURN(const MeshClip mesh_clip, ClipFor(catalog, named, request.clip()));
    ARMATURE_RETURN_IF_ERROR(ValidateClipTime(request.time(), "time"));
    SampleOptions sample;
    sample.interpolation = server::FromProto(request.interpolation());
    sample.wrap = server::FromProto(request.wrap());
    auto [positions, normals] = OutputsOf(mesh, response);
    ARMATURE_RETURN_IF_ERROR(SkinByClip(mesh, mesh_clip, request.time(), sample, options, positions, normals, ws.skin));
  } else {
    if (named.skeleton_name.empty())
      return Status::InvalidArgument("pose: mesh '" + named.name + "' has no skeleton to pose; give a clip");
    ARMATURE_ASSIGN_OR_RETURN(auto skeleton_ref, catalog.FindSkeleton(named.skeleton_name));
    const Skeleton& skeleton = *skeleton_ref.part->skeleton;
    ws.local.resize(skeleton.size());
    ARMATURE_RETURN_IF_ERROR(
        PoseFromArrays(skeleton, AsSpan(request.pose().rotations()), AsSpan(request.pose().translations()), ws.local)
            .WithContext("pose: "));
    auto [positions, normals] = OutputsOf(mesh, response);
    ARMATURE_RETURN_IF_ERROR(SkinPose(mesh, skeleton, ws.local, options, positions, normals, ws.skin));
  }
  response->set_mesh(named.name);
  response->set_vertex_count(static_cast<int>(mesh.vertex_count()));
  return Status::Ok();
}

Status SkinCharacter(const Catalog& catalog, const Limits& limits, const v1::SkinCharacterRequest& request,
                     v1::SkinCharacterResponse* response) {
  auto skeleton = catalog.FindSkeleton(request.skeleton());
  if (!skeleton.ok()) return skeleton.status().WithContext("skeleton: ");
  const std::string& name = skeleton->part->name;
  const std::vector<const NamedMesh*> meshes = catalog.MeshesOf(name);
  if (meshes.empty()) return Status::NotFound("skeleton: '" + name + "' has no meshes skinned to it (not a character)");
  v1::SkinMeshRequest each;
  each.set_clip(request.clip());
  each.set_time(request.time());
  each.set_interpolation(request.interpolation());
  each.set_wrap(request.wrap());
  if (request.has_pose()) *each.mutable_pose() = request.pose();
  each.set_method(request.method());
  if (request.has_motion()) *each.mutable_motion() = request.motion();
  response->set_skeleton(name);
  response->mutable_meshes()->Reserve(static_cast<int>(meshes.size()));
  for (const NamedMesh* mesh : meshes) {
    each.set_mesh(mesh->name);
    // The first mesh reports bad posing fields; naming the mesh tells which when only one fails.
    ARMATURE_RETURN_IF_ERROR(
        SkinMesh(catalog, limits, each, response->add_meshes()).WithContext("mesh '" + mesh->name + "': "));
  }
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
  ARMATURE_ASSIGN_OR_RETURN(auto bound, armature::BindMesh(*ref->part->mesh, *skeleton_ref->part->skeleton, options));
  const Mesh& mesh = bound.mesh;
  response->set_mesh(ref->part->name);
  response->set_skeleton(skeleton_ref->part->name);
  response->mutable_influence_offsets()->Add(mesh.influence_offsets.begin(), mesh.influence_offsets.end());
  response->mutable_influence_joints()->Reserve(static_cast<int>(mesh.influence_joints.size()));
  for (uint32_t k : mesh.influence_joints) response->add_influence_joints(mesh.joints[k]);  // skin → skeleton joint
  response->mutable_influence_weights()->Add(mesh.influence_weights.begin(), mesh.influence_weights.end());
  for (const std::string& w : bound.warnings) response->add_warnings(w);
  response->set_max_influences(static_cast<int>(mesh.max_influences()));
  return Status::Ok();
}

}  // namespace armature::server
