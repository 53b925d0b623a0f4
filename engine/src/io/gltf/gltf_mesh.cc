// glTF meshes → Mesh: primitives merged per mesh, skin influences, morph
// targets (kept sparse while read).
#include "gltf_importer.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "armature/engine/mesh/mesh.h"

namespace armature::gltf_internal {

Status Importer::ImportMesh(size_t m) {
  const tinygltf::Mesh& gm = model_.meshes[m];
  const std::string where = "meshes[" + std::to_string(m) + "]";
  ARMATURE_RETURN_IF_ERROR(CheckName(gm.name, where + ".name"));
  auto mesh = std::make_shared<Mesh>();
  mesh->name = used_mesh_names_.Take(gm.name.empty() ? std::to_string(m) : gm.name);
  const int node = instance_[m];
  const int skin = node >= 0 ? model_.nodes[static_cast<size_t>(node)].skin : -1;
  if (skin >= 0) {
    auto binding = ReadSkin(skin);
    if (!binding.ok()) return binding.status().WithContext("nodes[" + std::to_string(node) + "].skin: ");
    mesh->joints = std::move(binding->joints);
    mesh->inverse_bind = std::move(binding->inverse_bind);
    mesh->skeleton_root = binding->root;
  } else if (node >= 0) {
    // No skin: the mesh follows its node rigidly.
    mesh->joints = {joint_of_[static_cast<size_t>(node)]};
    mesh->inverse_bind = {Eigen::Affine3d::Identity()};
  } else {
    warnings_.push_back(where + " is not used by any node; imported unbound, in its own space");
  }
  if (gm.primitives.empty()) return Status::InvalidArgument(where + ".primitives is empty");

  MeshInProgress progress;
  for (size_t p = 0; p < gm.primitives.size(); ++p) {
    const size_t triangles_before = mesh->triangle_count();
    ARMATURE_RETURN_IF_ERROR(AppendPrimitive(gm.primitives[p], where + ".primitives[" + std::to_string(p) + "]", p == 0,
                                             skin, *mesh, progress));
    ARMATURE_RETURN_IF_ERROR(
        AddMaterialGroup(gm.primitives[p], where + ".primitives[" + std::to_string(p) + "]", triangles_before, *mesh));
  }
  if (!progress.any_normals) std::vector<Eigen::Vector3f>().swap(mesh->normals);  // the zeros' memory too
  if (progress.any_normals && !progress.missing_normals.empty()) {
    // A primitive's triangles only reference its own vertices, so the whole
    // mesh's vertex normals are each primitive's own.
    const auto computed = ComputeVertexNormals(mesh->positions, mesh->triangles);
    for (const auto& [begin, end] : progress.missing_normals)
      std::copy(computed.begin() + static_cast<ptrdiff_t>(begin), computed.begin() + static_cast<ptrdiff_t>(end),
                mesh->normals.begin() + static_cast<ptrdiff_t>(begin));
    warnings_.push_back(where + ": some primitives have no NORMAL; computed from their triangles");
  }
  FinishUvsAndMaterials(gm, where, *mesh);
  if (progress.zero_weight_vertices > 0)
    warnings_.push_back(where + ": " + std::to_string(progress.zero_weight_vertices) +
                        " vertices have all-zero weights; bound to their first listed joint");
  ARMATURE_RETURN_IF_ERROR(AddMorphTargets(gm, node, where, progress, *mesh));

  std::vector<std::string> mesh_warnings;
  ARMATURE_RETURN_IF_ERROR(FinalizeMesh(*mesh, &mesh_warnings).WithContext(where + ": "));
  for (const std::string& w : mesh_warnings) warnings_.push_back(where + ": " + w);
  contents_.meshes.push_back({name_ + "." + mesh->name, node >= 0 ? name_ : "", mesh});
  return Status::Ok();
}

// Morph targets: sparse deltas, names, default weights (the node's override the mesh's).
Status Importer::AddMorphTargets(const tinygltf::Mesh& gm, int node, const std::string& where, MeshInProgress& progress,
                                 Mesh& mesh) {
  std::vector<SparseTarget>& targets = progress.targets;
  std::vector<std::string> names(targets.size());
  for (size_t t = 0; t < targets.size(); ++t) names[t] = std::to_string(t);
  if (gm.extras.Has("targetNames")) {
    const tinygltf::Value& list = gm.extras.Get("targetNames");
    if (!list.IsArray() || list.ArrayLen() != targets.size())
      warnings_.push_back(where + ".extras.targetNames is not an array of " + std::to_string(targets.size()) +
                          " names; targets are named by index");
    else
      for (size_t t = 0; t < targets.size(); ++t)
        if (list.Get(static_cast<int>(t)).IsString()) {
          names[t] = list.Get(static_cast<int>(t)).Get<std::string>();
          ARMATURE_RETURN_IF_ERROR(CheckName(names[t], where + ".extras.targetNames[" + std::to_string(t) + "]"));
        }
  }
  for (size_t t = 0; t < targets.size(); ++t) {
    MorphTarget target;
    target.name = names[t];
    target.vertices = std::move(targets[t].vertices);
    target.position_deltas = std::move(targets[t].positions);
    if (targets[t].has_normals && progress.any_normals) target.normal_deltas = std::move(targets[t].normals);
    mesh.targets.push_back(std::move(target));
  }
  std::vector<double> weights = gm.weights;
  if (node >= 0 && !model_.nodes[static_cast<size_t>(node)].weights.empty())
    weights = model_.nodes[static_cast<size_t>(node)].weights;
  if (!weights.empty() && weights.size() != targets.size())
    return Status::InvalidArgument(where + ".weights: " + std::to_string(weights.size()) + " weights for " +
                                   std::to_string(targets.size()) + " morph targets");
  mesh.default_weights.assign(targets.size(), 0.f);
  for (size_t t = 0; t < weights.size(); ++t) {
    if (!std::isfinite(weights[t])) return Status::InvalidArgument(where + ".weights is not finite");
    mesh.default_weights[t] = static_cast<float>(weights[t]);
  }
  return Status::Ok();
}

namespace {

// Estimated bytes per element, as the mesh keeps it plus the decoding's copies:
// a vertex's position and normal (decoded floats, Vector3f, the layout's SoA
// copy) and its layout order; an index (decoded, then a triangle corner); a
// JOINTS_n/WEIGHTS_n set's four influences (decoded, kept, and the layout's
// joints, weights and pair offsets); a morph target's delta (decoded, and kept
// sparse as position and normal deltas and their vertex, when not zero).
constexpr uint64_t kVertexBytes = 3 * 24 + 4;
constexpr uint64_t kIndexBytes = 4 + 4;
constexpr uint64_t kInfluenceSetBytes = 4 * (4 + 4 + 4 + 4 + 2 + 4 + 4) + 4;
constexpr uint64_t kTargetVertexBytes = 2 * 12 + 4 + 2 * 12;

uint64_t SaturatingMul(uint64_t a, uint64_t b) {
  uint64_t r;
  return __builtin_mul_overflow(a, b, &r) ? UINT64_MAX : r;
}

uint64_t SaturatingSum(std::initializer_list<uint64_t> terms) {
  uint64_t sum = 0;
  for (uint64_t t : terms)
    if (__builtin_add_overflow(sum, t, &sum)) return UINT64_MAX;
  return sum;
}

}  // namespace

Status Importer::ChargeDecoded(uint64_t bytes, const std::string& where) {
  return ChargeDecodedBytes(&decoded_bytes_, bytes, limits_, where);
}

Status Importer::ChargePrimitive(const tinygltf::Primitive& prim, const std::string& where, uint64_t vertices,
                                 int skin) {
  uint64_t indices = vertices;
  if (prim.indices >= 0) {
    ARMATURE_ASSIGN_OR_RETURN(auto declared, reader_.Count(prim.indices, where + ".indices"));
    indices = declared;
  }
  uint64_t influence_sets = 0;
  if (skin >= 0)
    while (prim.attributes.contains("JOINTS_" + std::to_string(influence_sets))) ++influence_sets;
  uint64_t target_vertices = 0;
  for (const auto& target : prim.targets)
    target_vertices = SaturatingSum({target_vertices, SaturatingMul(vertices, target.size())});
  return ChargeDecoded(SaturatingSum({SaturatingMul(vertices, kVertexBytes), SaturatingMul(indices, kIndexBytes),
                                      SaturatingMul(SaturatingMul(vertices, influence_sets), kInfluenceSetBytes),
                                      SaturatingMul(target_vertices, kTargetVertexBytes)}),
                       where);
}

namespace {

// The accessor of a primitive's attribute `semantic`, or -1.
int AttributeAccessor(const tinygltf::Primitive& prim, const char* semantic) {
  auto it = prim.attributes.find(semantic);
  return it == prim.attributes.end() ? -1 : it->second;
}

// Every attribute of a primitive has as many elements as POSITION.
Status CheckCount(const AccessorData& d, const std::string& field, int accessor, size_t count) {
  if (d.count != count)
    return Status::InvalidArgument(field + ": accessor " + std::to_string(accessor) + " has " +
                                   std::to_string(d.count) + " elements, POSITION has " + std::to_string(count));
  return Status::Ok();
}

}  // namespace

Status Importer::AppendPrimitive(const tinygltf::Primitive& prim, const std::string& where, bool first, int skin,
                                 Mesh& mesh, MeshInProgress& progress) {
  PrimitiveSlot slot{prim, where, where + ".attributes.", mesh.positions.size(), 0};
  ARMATURE_RETURN_IF_ERROR(AppendPositions(slot, skin, mesh));
  ARMATURE_RETURN_IF_ERROR(AppendTriangles(slot, mesh));
  ARMATURE_RETURN_IF_ERROR(AppendNormals(slot, mesh, progress));
  ARMATURE_RETURN_IF_ERROR(AppendTexcoords(prim, slot.attrs, slot.base, slot.count, mesh));
  ARMATURE_RETURN_IF_ERROR(AppendInfluences(slot, skin, mesh, progress.zero_weight_vertices));
  return AppendMorphTargets(slot, first, progress.targets);
}

Status Importer::AppendPositions(PrimitiveSlot& slot, int skin, Mesh& mesh) {
  const tinygltf::Primitive& prim = slot.prim;
  const std::string& where = slot.where;
  const int position_accessor = AttributeAccessor(prim, "POSITION");
  if (position_accessor < 0) return Status::InvalidArgument(where + ".attributes has no POSITION");
  // Sizes before decoding: the mesh's vertices, and morph targets × vertices.
  ARMATURE_ASSIGN_OR_RETURN(const uint64_t declared, reader_.Count(position_accessor, slot.attrs + "POSITION"));
  const uint64_t vertices = static_cast<uint64_t>(slot.base) + std::min<uint64_t>(declared, UINT64_MAX / 2);
  if (vertices > limits_.max_mesh_vertices)
    return Status::ResourceExhausted(
        slot.attrs +
        "POSITION: " + OverImportLimitCount(vertices, "vertices", "max_mesh_vertices", limits_.max_mesh_vertices));
  uint64_t morph = 0;
  if (__builtin_mul_overflow(vertices, prim.targets.size(), &morph)) morph = UINT64_MAX;
  if (morph > limits_.max_morph_target_vertices)
    return Status::ResourceExhausted(
        where + ".targets: " +
        OverImportLimit(
            std::to_string(prim.targets.size()) + " morph targets × " + std::to_string(vertices) + " vertices =", morph,
            "max_morph_target_vertices", limits_.max_morph_target_vertices));
  ARMATURE_RETURN_IF_ERROR(ChargePrimitive(prim, where, declared, skin));
  std::vector<float> positions;
  ARMATURE_ASSIGN_OR_RETURN(const AccessorData pos, reader_.ReadFloats(position_accessor, slot.attrs + "POSITION",
                                                                       AccessorType::kVec3, {}, &positions));
  slot.count = pos.count;
  mesh.positions.reserve(slot.base + slot.count);  // exactly: doubling growth would hold up to twice the charge
  for (size_t v = 0; v < slot.count; ++v)
    mesh.positions.emplace_back(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
  return Status::Ok();
}

Status Importer::AppendTriangles(const PrimitiveSlot& slot, Mesh& mesh) {
  const tinygltf::Primitive& prim = slot.prim;
  const std::string& where = slot.where;
  const size_t base = slot.base, count = slot.count;
  std::vector<uint32_t> indices;
  if (prim.indices >= 0) {
    ARMATURE_RETURN_IF_ERROR(reader_
                                 .ReadUints(prim.indices, where + ".indices", AccessorType::kScalar,
                                            {kUnsignedByte, kUnsignedShort, kUnsignedInt}, &indices)
                                 .status());
    for (size_t i = 0; i < indices.size(); ++i)
      if (indices[i] >= count)
        return Status::InvalidArgument(where + ".indices: accessor " + std::to_string(prim.indices) + " element " +
                                       std::to_string(i) + " = " + std::to_string(indices[i]) + " is out of range (" +
                                       std::to_string(count) + " vertices)");
  } else {
    indices.resize(count);
    for (size_t i = 0; i < count; ++i) indices[i] = static_cast<uint32_t>(i);
  }
  const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
  auto tri = [&](uint32_t a, uint32_t b, uint32_t c) {
    mesh.triangles.insert(mesh.triangles.end(), {uint32_t(base + a), uint32_t(base + b), uint32_t(base + c)});
  };
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    for (size_t i = 0; i + 2 < indices.size(); i += 3) tri(indices[i], indices[i + 1], indices[i + 2]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 0; i + 2 < indices.size(); ++i)
      i % 2 == 0 ? tri(indices[i], indices[i + 1], indices[i + 2]) : tri(indices[i + 1], indices[i], indices[i + 2]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (size_t i = 1; i + 1 < indices.size(); ++i) tri(indices[0], indices[i], indices[i + 1]);
  } else if (mode >= 0 && mode <= 3) {
    warnings_.push_back(where + ": points/lines primitive; its vertices are kept without triangles");
  } else {
    return Status::InvalidArgument(where + ".mode " + std::to_string(mode) + " is not a glTF primitive mode");
  }
  return Status::Ok();
}

Status Importer::AppendNormals(const PrimitiveSlot& slot, Mesh& mesh, MeshInProgress& progress) {
  const size_t base = slot.base, count = slot.count;
  const int normal_accessor = AttributeAccessor(slot.prim, "NORMAL");
  if (normal_accessor < 0) {
    // Computed from the triangles once all primitives are in, if another
    // primitive has NORMAL.
    progress.missing_normals.emplace_back(base, base + count);
    mesh.normals.resize(base + count, Eigen::Vector3f::Zero());
    return Status::Ok();
  }
  std::vector<float> normals;
  ARMATURE_ASSIGN_OR_RETURN(const AccessorData nrm, reader_.ReadFloats(normal_accessor, slot.attrs + "NORMAL",
                                                                       AccessorType::kVec3, {}, &normals));
  ARMATURE_RETURN_IF_ERROR(CheckCount(nrm, slot.attrs + "NORMAL", normal_accessor, count));
  mesh.normals.resize(base);
  mesh.normals.reserve(base + count);
  for (size_t v = 0; v < count; ++v) mesh.normals.emplace_back(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]);
  progress.any_normals = true;
  return Status::Ok();
}

// Every JOINTS_n/WEIGHTS_n pair, checked: no negative weight, no joint outside the skin.
StatusOr<Importer::InfluenceSets> Importer::ReadInfluenceSets(const PrimitiveSlot& slot, int skin) {
  const std::string& attrs = slot.attrs;
  const size_t joint_count = model_.skins[static_cast<size_t>(skin)].joints.size();
  InfluenceSets sets;
  for (int set = 0;; ++set) {
    const std::string js = "JOINTS_" + std::to_string(set), ws = "WEIGHTS_" + std::to_string(set);
    const int ja = AttributeAccessor(slot.prim, js.c_str()), wa = AttributeAccessor(slot.prim, ws.c_str());
    if (ja < 0 && wa < 0) break;
    if (ja < 0 || wa < 0)
      return Status::InvalidArgument(attrs + (ja < 0 ? ws : js) + " has no matching " + (ja < 0 ? js : ws));
    std::vector<uint32_t>& joints = sets.joints.emplace_back();
    std::vector<float>& weights = sets.weights.emplace_back();
    ARMATURE_ASSIGN_OR_RETURN(const AccessorData jd, reader_.ReadUints(ja, attrs + js, AccessorType::kVec4,
                                                                       {kUnsignedByte, kUnsignedShort}, &joints));
    ARMATURE_RETURN_IF_ERROR(CheckCount(jd, attrs + js, ja, slot.count));
    ARMATURE_ASSIGN_OR_RETURN(const AccessorData wd, reader_.ReadFloats(wa, attrs + ws, AccessorType::kVec4,
                                                                        {kUnsignedByte, kUnsignedShort}, &weights));
    ARMATURE_RETURN_IF_ERROR(CheckCount(wd, attrs + ws, wa, slot.count));
    for (size_t i = 0; i < joints.size(); ++i) {
      const float w = weights[i];
      if (w < 0)
        return Status::InvalidArgument(attrs + ws + ": accessor " + std::to_string(wa) + " element " +
                                       std::to_string(i / 4) + " has a negative weight");
      if (w > 0 && joints[i] >= joint_count)
        return Status::InvalidArgument(attrs + js + ": accessor " + std::to_string(ja) + " element " +
                                       std::to_string(i / 4) + " uses joint " + std::to_string(joints[i]) +
                                       " but skin " + std::to_string(skin) + " has " + std::to_string(joint_count) +
                                       " joints");
    }
  }
  if (sets.joints.empty())
    return Status::InvalidArgument(slot.where + ": the node's skin " + std::to_string(skin) +
                                   " needs JOINTS_0 and WEIGHTS_0 attributes");
  return sets;
}

// Skin influences: a skinned primitive's nonzero weights per vertex; an
// unskinned primitive of a node-bound mesh, all on the mesh's one joint.
Status Importer::AppendInfluences(const PrimitiveSlot& slot, int skin, Mesh& mesh, size_t& zero_weight_vertices) {
  const size_t count = slot.count;
  if (skin < 0) {
    if (mesh.joints.empty()) return Status::Ok();
    if (AttributeAccessor(slot.prim, "JOINTS_0") >= 0)
      warnings_.push_back(slot.where + ": JOINTS_0 without a skin on the node; ignored");
    if (mesh.influence_offsets.empty()) mesh.influence_offsets.push_back(0);
    for (size_t v = 0; v < count; ++v) {
      mesh.influence_joints.push_back(0);
      mesh.influence_weights.push_back(1.f);
      mesh.influence_offsets.push_back(static_cast<uint32_t>(mesh.influence_joints.size()));
    }
    return Status::Ok();
  }
  ARMATURE_ASSIGN_OR_RETURN(const InfluenceSets sets, ReadInfluenceSets(slot, skin));
  const size_t joint_count = model_.skins[static_cast<size_t>(skin)].joints.size();
  if (mesh.influence_offsets.empty()) mesh.influence_offsets.push_back(0);
  for (size_t v = 0; v < count; ++v) {
    const size_t before = mesh.influence_joints.size();
    for (size_t s = 0; s < sets.joints.size(); ++s)
      for (size_t c = 0; c < 4; ++c)
        if (sets.weights[s][4 * v + c] > 0) {
          mesh.influence_joints.push_back(sets.joints[s][4 * v + c]);
          mesh.influence_weights.push_back(sets.weights[s][4 * v + c]);
        }
    if (mesh.influence_joints.size() == before) {
      // As three.js's normalizeSkinWeights: all weight on the first listed joint.
      ++zero_weight_vertices;
      const uint32_t j = sets.joints[0][4 * v];
      if (j >= joint_count)
        return Status::InvalidArgument(slot.attrs + "JOINTS_0: element " + std::to_string(v) + " uses joint " +
                                       std::to_string(j) + " but skin " + std::to_string(skin) + " has " +
                                       std::to_string(joint_count) + " joints");
      mesh.influence_joints.push_back(j);
      mesh.influence_weights.push_back(1.f);
    }
    mesh.influence_offsets.push_back(static_cast<uint32_t>(mesh.influence_joints.size()));
  }
  return Status::Ok();
}

// Morph targets: each target's nonzero POSITION/NORMAL deltas, kept sparse.
Status Importer::AppendMorphTargets(const PrimitiveSlot& slot, bool first, std::vector<SparseTarget>& targets) {
  const tinygltf::Primitive& prim = slot.prim;
  if (first) targets.resize(prim.targets.size());
  if (prim.targets.size() != targets.size())
    return Status::InvalidArgument(slot.where + ".targets: " + std::to_string(prim.targets.size()) +
                                   " targets, the first primitive has " + std::to_string(targets.size()));
  for (size_t t = 0; t < targets.size(); ++t) {
    SparseTarget& sparse = targets[t];
    const std::string twhere = slot.where + ".targets[" + std::to_string(t) + "].";
    std::vector<float> deltas[2];  // POSITION, NORMAL; empty when the target has none
    for (int k = 0; k < 2; ++k) {
      const char* semantic = k == 0 ? "POSITION" : "NORMAL";
      auto it = prim.targets[t].find(semantic);
      if (it == prim.targets[t].end()) continue;
      ARMATURE_ASSIGN_OR_RETURN(const AccessorData d,
                                reader_.ReadFloats(it->second, twhere + semantic, AccessorType::kVec3, {}, &deltas[k]));
      ARMATURE_RETURN_IF_ERROR(CheckCount(d, twhere + semantic, it->second, slot.count));
      if (k == 1) sparse.has_normals = true;
    }
    auto delta = [&](int k, size_t v) {
      return deltas[k].empty() ? Eigen::Vector3f::Zero().eval()
                               : Eigen::Vector3f(deltas[k][3 * v], deltas[k][3 * v + 1], deltas[k][3 * v + 2]);
    };
    for (size_t v = 0; v < slot.count; ++v) {
      const Eigen::Vector3f p = delta(0, v), n = delta(1, v);
      if (p.isZero(0) && n.isZero(0)) continue;
      sparse.vertices.push_back(static_cast<uint32_t>(slot.base + v));
      sparse.positions.push_back(p);
      sparse.normals.push_back(n);
    }
  }
  return Status::Ok();
}

Status Importer::AppendTexcoords(const tinygltf::Primitive& prim, const std::string& attrs, size_t base, size_t count,
                                 Mesh& mesh) {
  const auto it = prim.attributes.find("TEXCOORD_0");
  mesh.uvs.resize(base, Eigen::Vector2f::Zero());
  if (it == prim.attributes.end()) {
    mesh.uvs.resize(base + count, Eigen::Vector2f::Zero());
    return Status::Ok();
  }
  std::vector<float> uv;
  ARMATURE_ASSIGN_OR_RETURN(auto data, reader_.ReadFloats(it->second, attrs + "TEXCOORD_0", AccessorType::kVec2,
                                                          {kUnsignedByte, kUnsignedShort}, &uv));
  if (data.count != count)
    return Status::InvalidArgument(attrs + "TEXCOORD_0: accessor " + std::to_string(it->second) + " has " +
                                   std::to_string(data.count) + " elements, POSITION has " + std::to_string(count));
  for (size_t v = 0; v < count; ++v) mesh.uvs.emplace_back(uv[2 * v], uv[2 * v + 1]);
  return Status::Ok();
}

// UVs kept when a primitive has them (zeros for the others' vertices);
// material groups when any primitive has a material.
void Importer::FinishUvsAndMaterials(const tinygltf::Mesh& gm, const std::string& where, Mesh& mesh) {
  size_t with_uvs = 0;
  for (const tinygltf::Primitive& p : gm.primitives) with_uvs += p.attributes.count("TEXCOORD_0");
  if (with_uvs == 0)
    mesh.uvs.clear();
  else if (with_uvs < gm.primitives.size())
    warnings_.push_back(where + ": some primitives have no TEXCOORD_0; their vertices get UV (0, 0)");
  bool any_material = false;
  for (const MaterialGroup& g : mesh.material_groups) any_material |= g.material >= 0;
  if (!any_material) mesh.material_groups.clear();
}

// The primitive's triangles (from `first_triangle` on) as a material group,
// merged into the previous group when it has the same material.
Status Importer::AddMaterialGroup(const tinygltf::Primitive& prim, const std::string& where, size_t first_triangle,
                                  Mesh& mesh) {
  auto material = MaterialOf(prim.material);
  if (!material.ok()) return material.status().WithContext(where + ".material: ");
  const size_t count = mesh.triangle_count() - first_triangle;
  if (count == 0) return Status::Ok();
  int index = -1;
  if (*material) {
    const auto it = std::find(mesh.materials.begin(), mesh.materials.end(), *material);
    index = static_cast<int>(it - mesh.materials.begin());
    if (it == mesh.materials.end()) mesh.materials.push_back(*material);
  }
  if (!mesh.material_groups.empty() && mesh.material_groups.back().material == index)
    mesh.material_groups.back().triangle_count += static_cast<uint32_t>(count);
  else
    mesh.material_groups.push_back({static_cast<uint32_t>(first_triangle), static_cast<uint32_t>(count), index});
  return Status::Ok();
}

}  // namespace armature::gltf_internal
