// glTF export of meshes: one glTF mesh per Mesh, of one primitive per
// material group (sharing the vertex attributes and morph targets), and its
// skin, on a node of the skeleton.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "gltf_export.h"

namespace armature::gltf_export {
namespace {

constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;
constexpr int kArrayBuffer = TINYGLTF_TARGET_ARRAY_BUFFER;

// Positions as floats with the min and max glTF requires on POSITION.
int AddPositions(const std::vector<Eigen::Vector3f>& points, ModelBuilder& builder) {
  std::vector<float> xyz;
  xyz.reserve(3 * points.size());
  std::vector<double> lo(3, 0), hi(3, 0);
  for (size_t v = 0; v < points.size(); ++v) {
    for (int c = 0; c < 3; ++c) {
      xyz.push_back(points[v][c]);
      lo[c] = v ? std::min<double>(lo[c], points[v][c]) : points[v][c];
      hi[c] = v ? std::max<double>(hi[c], points[v][c]) : points[v][c];
    }
  }
  return builder.Add(std::span<const float>(xyz), kFloat, TINYGLTF_TYPE_VEC3, points.size(), kArrayBuffer,
                     std::move(lo), std::move(hi));
}

int AddVectors(const std::vector<Eigen::Vector3f>& vectors, ModelBuilder& builder) {
  std::vector<float> xyz;
  xyz.reserve(3 * vectors.size());
  for (const Eigen::Vector3f& v : vectors) xyz.insert(xyz.end(), {v.x(), v.y(), v.z()});
  return builder.AddFloats(xyz, TINYGLTF_TYPE_VEC3, vectors.size(), kArrayBuffer);
}

size_t InfluenceSets(const Mesh& mesh) {
  return mesh.skinned() ? std::max<size_t>(1, (mesh.max_influences() + 3) / 4) : 0;
}

// JOINTS_n and WEIGHTS_n: four influences per set, in the mesh's order.
void AddInfluences(const Mesh& mesh, tinygltf::Primitive& primitive, ModelBuilder& builder) {
  const size_t n = mesh.vertex_count(), sets = InfluenceSets(mesh);
  for (size_t s = 0; s < sets; ++s) {
    std::vector<uint16_t> joints(4 * n, 0);
    std::vector<float> weights(4 * n, 0.f);
    for (size_t v = 0; v < n; ++v) {
      const uint32_t begin = mesh.influence_offsets[v], end = mesh.influence_offsets[v + 1];
      for (size_t k = 0; k < 4 && begin + 4 * s + k < end; ++k) {
        joints[4 * v + k] = static_cast<uint16_t>(mesh.influence_joints[begin + 4 * s + k]);
        weights[4 * v + k] = mesh.influence_weights[begin + 4 * s + k];
      }
    }
    const std::string index = std::to_string(s);
    primitive.attributes["JOINTS_" + index] = builder.Add(
        std::span<const uint16_t>(joints), TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4, n, kArrayBuffer);
    primitive.attributes["WEIGHTS_" + index] = builder.AddFloats(weights, TINYGLTF_TYPE_VEC4, n, kArrayBuffer);
  }
}

// Morph targets as dense POSITION (and NORMAL) deltas, their default weights
// and names (extras.targetNames, as three.js and Blender read them).
void AddTargets(const Mesh& mesh, tinygltf::Primitive& primitive, tinygltf::Mesh& out, ModelBuilder& builder) {
  if (mesh.targets.empty()) return;
  const bool normals =
      !mesh.normals.empty() && std::any_of(mesh.targets.begin(), mesh.targets.end(),
                                           [](const MorphTarget& t) { return !t.normal_deltas.empty(); });
  tinygltf::Value::Array names;
  for (const MorphTarget& target : mesh.targets) {
    std::vector<Eigen::Vector3f> positions(mesh.vertex_count(), Eigen::Vector3f::Zero());
    std::vector<Eigen::Vector3f> deltas(normals ? mesh.vertex_count() : 0, Eigen::Vector3f::Zero());
    for (size_t i = 0; i < target.vertices.size(); ++i) {
      positions[target.vertices[i]] = target.position_deltas[i];
      if (normals && !target.normal_deltas.empty()) deltas[target.vertices[i]] = target.normal_deltas[i];
    }
    std::map<std::string, int> attributes{{"POSITION", AddPositions(positions, builder)}};
    if (normals) attributes["NORMAL"] = AddVectors(deltas, builder);
    primitive.targets.push_back(std::move(attributes));
    names.emplace_back(target.name);
  }
  for (size_t t = 0; t < mesh.targets.size(); ++t)
    out.weights.push_back(t < mesh.default_weights.size() ? mesh.default_weights[t] : 0.0);
  tinygltf::Value::Object extras;
  extras.emplace("targetNames", tinygltf::Value(std::move(names)));
  out.extras = tinygltf::Value(std::move(extras));
}

// The mesh's triangles as one primitive, or one per material group: the
// groups share `shared`'s vertex attributes and morph targets.
void AddPrimitives(const Mesh& mesh, const tinygltf::Primitive& shared, tinygltf::Mesh& out, MaterialWriter& materials,
                   ModelBuilder& builder) {
  auto indices = [&](size_t first, size_t count) {
    return builder.Add(std::span<const uint32_t>(mesh.triangles).subspan(3 * first, 3 * count),
                       TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, 3 * count,
                       TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  };
  if (mesh.material_groups.empty()) {
    out.primitives.push_back(shared);
    if (!mesh.triangles.empty()) out.primitives.back().indices = indices(0, mesh.triangle_count());
    return;
  }
  for (const MaterialGroup& group : mesh.material_groups) {
    tinygltf::Primitive primitive = shared;
    primitive.indices = indices(group.first_triangle, group.triangle_count);
    if (group.material >= 0) primitive.material = materials.Add(*mesh.materials[static_cast<size_t>(group.material)]);
    out.primitives.push_back(std::move(primitive));
  }
}

int AddSkin(const Mesh& mesh, ModelBuilder& builder) {
  std::vector<float> matrices;
  matrices.reserve(16 * mesh.inverse_bind.size());
  for (const Eigen::Affine3d& m : mesh.inverse_bind) {
    const Eigen::Matrix4f f = m.matrix().cast<float>();  // column-major, as glTF
    matrices.insert(matrices.end(), f.data(), f.data() + 16);
  }
  tinygltf::Skin skin;
  skin.joints = mesh.joints;  // node j is joint j
  skin.skeleton = mesh.skeleton_root;
  skin.inverseBindMatrices = builder.AddFloats(matrices, TINYGLTF_TYPE_MAT4, mesh.inverse_bind.size());
  builder.model().skins.push_back(std::move(skin));
  return static_cast<int>(builder.model().skins.size()) - 1;
}

// The node to hold a skinned mesh: a free root first, then any free joint;
// an unbound mesh (or one finding no free joint) gets a new root node.
int MeshNode(const Mesh& mesh, const Skeleton& skeleton, tinygltf::Model& model) {
  if (mesh.skinned()) {
    for (int pass = 0; pass < 2; ++pass)
      for (size_t j = 0; j < skeleton.size(); ++j)
        if ((pass == 1 || skeleton.parents[j] < 0) && model.nodes[j].mesh < 0) return static_cast<int>(j);
  }
  tinygltf::Node node;
  node.name = mesh.name;
  model.nodes.push_back(std::move(node));
  const int index = static_cast<int>(model.nodes.size()) - 1;
  model.scenes[0].nodes.push_back(index);
  return index;
}

}  // namespace

uint64_t MeshByteEstimate(const Mesh& mesh) {
  const uint64_t n = mesh.vertex_count();
  uint64_t per_vertex = 12 + (mesh.normals.empty() ? 0 : 12) + 24 * InfluenceSets(mesh);
  per_vertex = Add(per_vertex, Mul(mesh.targets.size(), mesh.normals.empty() ? 12 : 24));
  uint64_t bytes = Add(Mul(n, per_vertex), Mul(4, mesh.triangles.size()));
  bytes = Add(bytes, Mul(64, mesh.inverse_bind.size()));
  return Add(bytes, Mul(4 * 2 + 4, 8 + mesh.targets.size()));  // alignment of each view
}

StatusOr<std::vector<int>> AddMeshes(std::span<const Mesh* const> meshes, const Skeleton& skeleton,
                                     ModelBuilder& builder) {
  std::vector<int> nodes;
  MaterialWriter materials(builder);
  for (const Mesh* mesh : meshes) {
    if (mesh->influence_offsets.size() != (mesh->skinned() ? mesh->vertex_count() + 1 : 0) ||
        mesh->inverse_bind.size() != mesh->joints.size())
      return Status::InvalidArgument("glTF export: mesh '" + mesh->name + "' is not finalized");
    if (mesh->joints.size() > UINT16_MAX + size_t{1})
      return Status::InvalidArgument("glTF export: mesh '" + mesh->name + "' has " +
                                     std::to_string(mesh->joints.size()) + " skin joints, over 65536");
    tinygltf::Primitive primitive;
    primitive.mode = mesh->triangles.empty() ? TINYGLTF_MODE_POINTS : TINYGLTF_MODE_TRIANGLES;
    primitive.attributes["POSITION"] = AddPositions(mesh->positions, builder);
    if (!mesh->normals.empty()) primitive.attributes["NORMAL"] = AddVectors(mesh->normals, builder);
    if (!mesh->uvs.empty()) {
      std::vector<float> uv;
      uv.reserve(2 * mesh->uvs.size());
      for (const Eigen::Vector2f& t : mesh->uvs) uv.insert(uv.end(), {t.x(), t.y()});
      primitive.attributes["TEXCOORD_0"] = builder.AddFloats(uv, TINYGLTF_TYPE_VEC2, mesh->uvs.size(), kArrayBuffer);
    }
    AddInfluences(*mesh, primitive, builder);
    tinygltf::Mesh out;
    out.name = mesh->name;
    AddTargets(*mesh, primitive, out, builder);
    AddPrimitives(*mesh, primitive, out, materials, builder);
    tinygltf::Model& model = builder.model();
    model.meshes.push_back(std::move(out));
    const int node = MeshNode(*mesh, skeleton, model);
    model.nodes[static_cast<size_t>(node)].mesh = static_cast<int>(model.meshes.size()) - 1;
    if (mesh->skinned()) model.nodes[static_cast<size_t>(node)].skin = AddSkin(*mesh, builder);
    nodes.push_back(node);
  }
  return nodes;
}

}  // namespace armature::gltf_export
