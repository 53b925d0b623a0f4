#include "server/mesh/mesh_convert.h"

#include <google/protobuf/io/coded_stream.h>

#include "armature/engine/anim/joint_map.h"
#include "server/assets/motion_convert.h"
#include "server/rpc/request_validation.h"

namespace armature::server {

StatusOr<SkinningMethod> FromProto(v1::SkinningMethod method) {
  switch (method) {
    case v1::SKINNING_METHOD_UNSPECIFIED:
    case v1::LBS: return SkinningMethod::kLinear;
    case v1::DQS: return SkinningMethod::kDualQuaternion;
    default: return Status::InvalidArgument("method: unknown skinning method " + std::to_string(method));
  }
}

StatusOr<MeshClip> ClipFor(const Catalog& catalog, const NamedMesh& mesh, const std::string& name) {
  auto clip_ref = catalog.FindClip(name);
  if (!clip_ref.ok()) return clip_ref.status().WithContext("clip: ");
  MeshClip out;
  out.clip_ref = std::move(*clip_ref);
  if (mesh.skeleton_name.empty() || out.clip_ref.part->skeleton_name == mesh.skeleton_name) return out;
  auto skeleton_ref = catalog.FindSkeleton(mesh.skeleton_name);
  if (!skeleton_ref.ok()) return skeleton_ref.status().WithContext("mesh '" + mesh.name + "': ");
  out.skeleton_ref = std::move(*skeleton_ref);
  const Status mapped = MapJointsByName(*out.skeleton_ref.part->skeleton, *out.clip_ref.part->runtime->skeleton,
                                        "the mesh's skeleton '" + mesh.skeleton_name + "'", out.joint_map);
  if (!mapped.ok())
    return Status::InvalidArgument("clip: '" + name + "' animates skeleton '" + out.clip_ref.part->skeleton_name +
                                   "', which " + mapped.message());
  return out;
}

Status SkinByClip(const Mesh& mesh, const MeshClip& mesh_clip, double time, const SampleOptions& sample,
                  const SkinningOptions& options, std::span<float> positions, std::span<float> normals,
                  SkinningWorkspace& workspace) {
  ClipSkinningTime at{time, sample.wrap, sample.interpolation, nullptr, {}};
  if (mesh_clip.skeleton_ref.part != nullptr) {
    at.onto = mesh_clip.skeleton_ref.part->skeleton.get();
    at.map = mesh_clip.joint_map;
  }
  return SkinClip(mesh, *mesh_clip.clip_ref.part->runtime, at, options, positions, normals, workspace);
}

StatusOr<MotionPlan> MotionFor(const Catalog& catalog, const NamedMesh& mesh, const v1::Motion& motion,
                               const Limits& limits) {
  ARMATURE_RETURN_IF_ERROR(ValidateMotion(motion, limits, "motion"));
  const std::string& first = motion.layers(0).clip();
  auto clip = catalog.FindClip(first);
  if (!clip.ok()) return clip.status().WithContext("motion.layers[0]: ");
  if (!mesh.skeleton_name.empty() && clip->part->skeleton_name != mesh.skeleton_name)
    return Status::InvalidArgument("motion.layers[0] (clip '" + first + "'): animates skeleton '" +
                                   clip->part->skeleton_name + "', not the mesh's skeleton '" + mesh.skeleton_name +
                                   "'");
  return BindMotionProto(catalog, motion, limits, "motion");
}

namespace {

// What an answer carrying `mesh` holds: positions and normals (and triangle indices and UVs).
ReplyContent MeshReply(const Mesh& mesh, bool triangles) {
  ReplyContent reply;
  reply.floats = static_cast<double>(mesh.vertex_count()) * 3 * (mesh.normals.empty() ? 1 : 2);
  if (triangles) reply.floats += 2 * static_cast<double>(mesh.uvs.size());  // the geometry's UVs (u, v)
  reply.proto_overhead = 64;
  reply.json_overhead = 64;  // {"mesh":…,"vertexCount":…,"positions":[],"normals":[]}
  if (triangles)
    for (uint32_t index : mesh.triangles) {
      reply.proto_overhead += google::protobuf::io::CodedOutputStream::VarintSize32(index);
      reply.json_overhead += 1 + (index < 10 ? 1 : index < 100 ? 2 : index < 1000 ? 3 : index < 10000 ? 4 : 7);
    }
  return reply;
}

}  // namespace

Status ValidateMeshReply(const Mesh& mesh, bool triangles, const Limits& limits, const std::string& rpc,
                         ReplyEncoding encoding) {
  ReplyContent reply = MeshReply(mesh, triangles);
  reply.how = std::to_string(mesh.vertex_count()) + " vertices" +
              (triangles ? " and " + std::to_string(mesh.triangles.size() / 3) + " triangles" : "") +
              "; imports are capped by --max-mesh-vertices";
  return ValidateReplySize(reply, encoding, limits, rpc);
}

Status ValidateMeshReply(const Catalog& catalog, const std::string& name, bool triangles, const Limits& limits,
                         const std::string& rpc, ReplyEncoding encoding) {
  auto ref = catalog.FindMesh(name);
  if (!ref.ok()) return Status::Ok();  // the RPC itself reports it
  return ValidateMeshReply(*ref->part->mesh, triangles, limits, rpc, encoding);
}

Status ValidateCharacterReply(const std::vector<const NamedMesh*>& meshes, const Limits& limits, const std::string& rpc,
                              ReplyEncoding encoding) {
  ReplyContent reply;
  size_t vertices = 0;
  for (const NamedMesh* mesh : meshes) {
    const ReplyContent one = MeshReply(*mesh->mesh, false);
    reply.floats += one.floats;
    reply.proto_overhead += one.proto_overhead;
    reply.json_overhead += one.json_overhead;
    vertices += mesh->mesh->vertex_count();
  }
  reply.how = std::to_string(meshes.size()) + " meshes, " + std::to_string(vertices) +
              " vertices in all; imports are capped by --max-mesh-vertices";
  return ValidateReplySize(reply, encoding, limits, rpc);
}

}  // namespace armature::server
