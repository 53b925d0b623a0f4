// FBX meshes (assimp's, one per geometry and material) → Mesh: triangles,
// normals, UVs, the skin (bones' offset matrices and weights) and morph
// targets (assimp's anim meshes, as sparse deltas).
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "armature/base/utf8.h"
#include "fbx_importer.h"

namespace armature::fbx_internal {

namespace {

bool Finite(const aiVector3D& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Eigen::Vector3f ToEigen(const aiVector3D& v) { return {v.x, v.y, v.z}; }

}  // namespace

Status Importer::ImportMesh(unsigned m) {
  const aiMesh& am = *scene_.mMeshes[m];
  const std::string given = am.mName.C_Str();
  const std::string where = "FBX mesh " + std::to_string(m) + " '" + EscapeForMessage(given) + "'";
  if (!IsValidUtf8(given)) return Status::InvalidArgument(where + ": the name is not valid UTF-8");
  const uint64_t n = am.mNumVertices;
  if (n > limits_.max_mesh_vertices)
    return Status::ResourceExhausted(
        where + ": " + OverImportLimitCount(n, "vertices", "max_mesh_vertices", limits_.max_mesh_vertices));
  if (n * am.mNumAnimMeshes > limits_.max_morph_target_vertices)
    return Status::ResourceExhausted(where + ": " +
                                     OverImportLimitCount(n * am.mNumAnimMeshes, "morph target vertices",
                                                          "max_morph_target_vertices",
                                                          limits_.max_morph_target_vertices));
  // Positions, normals, UVs, triangles, up to 8 influences, each target's deltas.
  ARMATURE_RETURN_IF_ERROR(
      ChargeDecoded(n * (12 + 12 + 8 + 8 * 8 + 24ull * am.mNumAnimMeshes) + 12ull * am.mNumFaces, where));
  if (n == 0 || am.mVertices == nullptr) {
    warnings_.push_back(where + " has no vertices; left out");
    return Status::Ok();
  }
  auto mesh = std::make_shared<Mesh>();
  mesh->name = used_mesh_names_.Take(given.empty() ? std::to_string(m) : given);
  mesh->positions.reserve(n);
  for (unsigned v = 0; v < n; ++v) {
    if (!Finite(am.mVertices[v]))
      return Status::InvalidArgument(where + ": vertex " + std::to_string(v) + " is not finite");
    mesh->positions.push_back(ToEigen(am.mVertices[v]));
  }
  size_t other_faces = 0;
  for (unsigned f = 0; f < am.mNumFaces; ++f) {
    const aiFace& face = am.mFaces[f];
    if (face.mNumIndices != 3) {
      ++other_faces;  // points and lines draw nothing
      continue;
    }
    for (unsigned c = 0; c < 3; ++c) {
      if (face.mIndices[c] >= n)
        return Status::InvalidArgument(where + ": face " + std::to_string(f) + " names vertex " +
                                       std::to_string(face.mIndices[c]) + " of " + std::to_string(n));
      mesh->triangles.push_back(face.mIndices[c]);
    }
  }
  if (other_faces > 0) warnings_.push_back(where + ": " + std::to_string(other_faces) + " points and lines left out");
  bool normals_ok = am.mNormals != nullptr;
  for (unsigned v = 0; normals_ok && v < n; ++v) normals_ok = Finite(am.mNormals[v]);
  if (normals_ok) {
    mesh->normals.reserve(n);
    for (unsigned v = 0; v < n; ++v) mesh->normals.push_back(ToEigen(am.mNormals[v]));
  } else {
    mesh->normals = ComputeVertexNormals(mesh->positions, mesh->triangles);
  }
  if (am.mTextureCoords[0] != nullptr) {
    mesh->uvs.reserve(n);
    // FBX's V runs up, glTF's (the Mesh's convention) down.
    for (unsigned v = 0; v < n; ++v)
      mesh->uvs.emplace_back(am.mTextureCoords[0][v].x, 1.0f - am.mTextureCoords[0][v].y);
  }
  const int node_joint = node_joint_of_mesh_[m];
  if (am.mNumBones > 0 || node_joint >= 0) ARMATURE_RETURN_IF_ERROR(AddSkin(am, node_joint, where, *mesh));
  if (node_joint < 0 && am.mNumBones == 0)
    warnings_.push_back(where + " is not shown by any node; imported unbound, in its own space");
  ARMATURE_RETURN_IF_ERROR(AddMorphTargets(am, where, *mesh));
  std::vector<std::string> mesh_warnings;
  ARMATURE_RETURN_IF_ERROR(FinalizeMesh(*mesh, &mesh_warnings).WithContext(where + ": "));
  for (const std::string& w : mesh_warnings) warnings_.push_back(where + ": " + w);
  contents_.meshes.push_back({name_ + "." + mesh->name, mesh->skinned() ? name_ : "", mesh});
  return Status::Ok();
}

// The bones' joints and offset matrices (mesh space → bone space at bind), and
// each vertex's weights. A vertex no bone weighs follows the mesh's node; a
// mesh without bones follows it rigidly.
Status Importer::AddSkin(const aiMesh& am, int node_joint, const std::string& where, Mesh& mesh) {
  const size_t n = mesh.positions.size();
  std::vector<std::vector<std::pair<uint32_t, float>>> influences(n);
  for (unsigned b = 0; b < am.mNumBones; ++b) {
    const aiBone& bone = *am.mBones[b];
    const std::string bone_name = bone.mName.C_Str();
    const int joint = JointNamed(bone_name);
    if (joint < 0) return Status::InvalidArgument(where + ": bone '" + EscapeForMessage(bone_name) + "' names no node");
    const Eigen::Matrix4d offset = ToEigen(bone.mOffsetMatrix);
    if (!offset.allFinite())
      return Status::InvalidArgument(where + ": bone '" + EscapeForMessage(bone_name) +
                                     "' has a non-finite offset matrix");
    mesh.joints.push_back(joint);
    mesh.inverse_bind.emplace_back(offset);
    for (unsigned w = 0; w < bone.mNumWeights; ++w) {
      const aiVertexWeight& vw = bone.mWeights[w];
      if (vw.mVertexId >= n)
        return Status::InvalidArgument(where + ": bone '" + EscapeForMessage(bone_name) + "' weighs vertex " +
                                       std::to_string(vw.mVertexId) + " of " + std::to_string(n));
      if (std::isfinite(vw.mWeight) && vw.mWeight > 0) influences[vw.mVertexId].emplace_back(b, vw.mWeight);
    }
  }
  size_t unweighted = 0;
  for (const auto& list : influences) unweighted += list.empty() ? 1 : 0;
  uint32_t node_skin_joint = 0;
  if (unweighted > 0) {
    if (node_joint < 0)
      return Status::InvalidArgument(where + ": " + std::to_string(unweighted) +
                                     " vertices have no bone weight and the mesh is on no node");
    node_skin_joint = static_cast<uint32_t>(mesh.joints.size());
    mesh.joints.push_back(node_joint);
    mesh.inverse_bind.push_back(Eigen::Affine3d::Identity());
    if (am.mNumBones > 0)
      warnings_.push_back(where + ": " + std::to_string(unweighted) +
                          " vertices have no bone weight; they follow the mesh's node");
  }
  mesh.influence_offsets.reserve(n + 1);
  mesh.influence_offsets.push_back(0);
  for (const auto& list : influences) {
    if (list.empty()) {
      mesh.influence_joints.push_back(node_skin_joint);
      mesh.influence_weights.push_back(1.0f);
    }
    for (const auto& [joint, weight] : list) {
      mesh.influence_joints.push_back(joint);
      mesh.influence_weights.push_back(weight);
    }
    mesh.influence_offsets.push_back(static_cast<uint32_t>(mesh.influence_joints.size()));
  }
  return Status::Ok();
}

// assimp's anim meshes hold whole positions (and normals); a target keeps only
// the vertices it moves.
Status Importer::AddMorphTargets(const aiMesh& am, const std::string& where, Mesh& mesh) {
  UniqueNames used;
  for (unsigned t = 0; t < am.mNumAnimMeshes; ++t) {
    const aiAnimMesh& target = *am.mAnimMeshes[t];
    const std::string target_where = where + " morph target " + std::to_string(t);
    if (target.mVertices == nullptr || target.mNumVertices != am.mNumVertices)
      return Status::InvalidArgument(target_where + ": has " + std::to_string(target.mNumVertices) + " positions for " +
                                     std::to_string(am.mNumVertices) + " vertices");
    const std::string given = target.mName.C_Str();
    if (!IsValidUtf8(given)) return Status::InvalidArgument(target_where + ": the name is not valid UTF-8");
    MorphTarget out;
    out.name = used.Take(given.empty() ? std::to_string(t) : given);
    const bool normals = target.mNormals != nullptr && am.mNormals != nullptr;
    for (unsigned v = 0; v < am.mNumVertices; ++v) {
      if (!Finite(target.mVertices[v]) || (normals && !Finite(target.mNormals[v])))
        return Status::InvalidArgument(target_where + ": vertex " + std::to_string(v) + " is not finite");
      const Eigen::Vector3f delta = ToEigen(target.mVertices[v]) - ToEigen(am.mVertices[v]);
      const Eigen::Vector3f normal_delta =
          normals ? Eigen::Vector3f(ToEigen(target.mNormals[v]) - ToEigen(am.mNormals[v])) : Eigen::Vector3f::Zero();
      if (delta.isZero(0) && normal_delta.isZero(0)) continue;
      out.vertices.push_back(v);
      out.position_deltas.push_back(delta);
      if (normals) out.normal_deltas.push_back(normal_delta);
    }
    mesh.targets.push_back(std::move(out));
    mesh.default_weights.push_back(std::isfinite(target.mWeight) ? target.mWeight : 0.0f);
  }
  return Status::Ok();
}

}  // namespace armature::fbx_internal
