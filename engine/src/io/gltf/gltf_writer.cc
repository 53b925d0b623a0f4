// glTF export: the orchestration, the model's buffer, the skeleton's nodes
// and the size estimate. The animation is written in gltf_export_animation.cc,
// meshes and skins in gltf_export_mesh.cc.
#include "armature/engine/io/gltf/gltf_writer.h"

#include <cmath>
#include <exception>
#include <limits>
#include <sstream>
#include <utility>

#include "armature/engine/anim/compression/error_bound.h"
#include "armature/engine/mesh/mesh.h"
#include "gltf_export.h"

namespace armature::gltf_export {

uint64_t Add(uint64_t a, uint64_t b) {
  uint64_t r;
  return __builtin_add_overflow(a, b, &r) ? UINT64_MAX : r;
}

uint64_t Mul(uint64_t a, uint64_t b) {
  uint64_t r;
  return __builtin_mul_overflow(a, b, &r) ? UINT64_MAX : r;
}

StatusOr<float> ToFloat(double x, const std::string& where) {
  if (!std::isfinite(x) || std::abs(x) > std::numeric_limits<float>::max())
    return Status::InvalidArgument(where + ": " + std::to_string(x) + " cannot be written as a 32-bit float");
  return static_cast<float>(x);
}

ModelBuilder::ModelBuilder(uint64_t reserve_bytes, const char* generator) {
  model_.asset.version = "2.0";
  model_.asset.generator = generator;
  model_.buffers.emplace_back();
  model_.buffers[0].data.reserve(reserve_bytes);
}

StatusOr<int> ModelBuilder::AddTimes(const std::vector<double>& times, const std::string& where) {
  if (auto it = times_.find(times); it != times_.end()) return it->second;
  std::vector<float> f(times.size());
  for (size_t k = 0; k < times.size(); ++k) {
    ARMATURE_ASSIGN_OR_RETURN(auto t, ToFloat(times[k], where + " time " + std::to_string(k)));
    // Times closer than a float can tell apart stay strictly increasing.
    f[k] = k > 0 && t <= f[k - 1] ? std::nextafter(f[k - 1], std::numeric_limits<float>::infinity()) : t;
  }
  std::vector<double> lo, hi;
  if (!f.empty()) lo = {f.front()}, hi = {f.back()};
  const int accessor = Add(std::span<const float>(f), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, f.size(), 0,
                           std::move(lo), std::move(hi));
  times_.emplace(times, accessor);
  return accessor;
}

StatusOr<std::string> ModelBuilder::Write(bool binary) {
  // A glTF buffer holds at least one byte: a file with no binary data (a clip
  // without keys, no meshes) has no buffer at all. Written empty, a .gltf had
  // the data uri "data:application/octet-stream;base64," that tinygltf refuses.
  if (model_.buffers[0].data.empty() && model_.bufferViews.empty()) model_.buffers.clear();
  std::ostringstream out;
  tinygltf::TinyGLTF writer;
  try {  // the JSON library throws on what it cannot encode
    if (!writer.WriteGltfSceneToStream(&model_, out, false, binary))
      return Status::Internal("glTF export: tinygltf could not write the model");
  } catch (const std::exception& e) {
    return Status::InvalidArgument(std::string("glTF export: ") + e.what());
  }
  return std::move(out).str();
}

void AddSkeletonNodes(const Skeleton& skeleton, tinygltf::Model& model) {
  model.nodes.resize(skeleton.size());
  tinygltf::Scene scene;
  for (size_t j = 0; j < skeleton.size(); ++j) {
    tinygltf::Node& node = model.nodes[j];
    node.name = skeleton.names[j];
    // Doubles in the JSON: the rest pose survives exactly.
    const Trs& rest = skeleton.rest[j];
    if (!rest.translation.isZero(0))
      node.translation = {rest.translation.x(), rest.translation.y(), rest.translation.z()};
    if (rest.rotation.coeffs() != Eigen::Quaterniond::Identity().coeffs())
      node.rotation = {rest.rotation.x(), rest.rotation.y(), rest.rotation.z(), rest.rotation.w()};
    if (rest.scale != Eigen::Vector3d::Ones()) node.scale = {rest.scale.x(), rest.scale.y(), rest.scale.z()};
    const int parent = skeleton.parents[j];
    if (parent >= 0)
      model.nodes[static_cast<size_t>(parent)].children.push_back(static_cast<int>(j));
    else
      scene.nodes.push_back(static_cast<int>(j));
  }
  model.scenes.push_back(std::move(scene));
  model.defaultScene = 0;
}

}  // namespace armature::gltf_export

namespace armature {

using namespace gltf_export;

uint64_t GltfExportByteEstimate(const Clip& clip, std::span<const Mesh* const> meshes, bool binary) {
  uint64_t json = 1024, bin = AnimationByteEstimate(clip);
  if (clip.skeleton) {
    for (const std::string& name : clip.skeleton->names)  // a name escaped as \uXXXX at worst
      json = Add(json, Add(kJsonBytesPerObject, Mul(6, name.size())));
  }
  for (const Mesh* mesh : meshes) {
    bin = Add(bin, MeshByteEstimate(*mesh));
    json = Add(json, Add(Mul(kJsonBytesPerObject, 16 + 4 * mesh->targets.size()), Mul(12, mesh->name.size())));
    for (const MorphTarget& target : mesh->targets) json = Add(json, Mul(6, target.name.size() + 3));
  }
  bin = Add(bin, MaterialByteEstimate(meshes, &json));
  // A GLB holds the buffer as is; a .gltf as base64 (4 characters per 3 bytes).
  return Add(json, binary ? Add(bin, 32) : Add(Mul(bin / 3 + 1, 4), 64));
}

StatusOr<std::string> ExportGltf(const Clip& clip, std::span<const Mesh* const> meshes,
                                 const GltfExportOptions& options) {
  ARMATURE_RETURN_IF_ERROR(clip.Validate().WithContext("glTF export: "));
  const Skeleton& skeleton = *clip.skeleton;
  for (size_t m = 0; m < meshes.size(); ++m) {
    for (int joint : meshes[m]->joints)
      if (joint < 0 || static_cast<size_t>(joint) >= skeleton.size())
        return Status::InvalidArgument("glTF export: mesh '" + meshes[m]->name + "' is skinned to joint " +
                                       std::to_string(joint) + ", outside the clip's skeleton of " +
                                       std::to_string(skeleton.size()) + " joints");
  }
  // The animation's name comes on top of the estimate (escaped at worst).
  const uint64_t estimate =
      Add(GltfExportByteEstimate(clip, meshes, options.binary), Mul(6, options.animation_name.size()));
  if (estimate > options.max_bytes)
    return Status::ResourceExhausted("glTF export: the file would take up to " + std::to_string(estimate) +
                                     " bytes, over the limit of " + std::to_string(options.max_bytes));

  ModelBuilder builder(std::min<uint64_t>(estimate, options.max_bytes));
  AddSkeletonNodes(skeleton, builder.model());
  // glTF means metres; a skeleton in other units (a BVH one in centimetres)
  // says so, so that a clip stored as this file keeps its error bound's scale.
  if (const double units = UnitsPerCentimetre(skeleton); units != 0.01) {
    tinygltf::Value::Object extras;
    extras.emplace(kUnitsPerCentimetreExtra, tinygltf::Value(units));
    builder.model().asset.extras = tinygltf::Value(std::move(extras));
  }
  ARMATURE_ASSIGN_OR_RETURN(auto mesh_nodes, AddMeshes(meshes, skeleton, builder));
  std::map<std::string, int> node_of_mesh;
  for (size_t m = 0; m < meshes.size(); ++m) node_of_mesh.emplace(meshes[m]->name, mesh_nodes[m]);
  ARMATURE_RETURN_IF_ERROR(AddAnimation(clip, options.animation_name, node_of_mesh, builder));
  return builder.Write(options.binary);
}

}  // namespace armature
