// glTF 2.0 import: the Importer's orchestration and its skeleton (nodes and
// skins). Meshes are read in gltf_mesh.cc, animations in gltf_animation.cc,
// bytes through tinygltf in gltf_load.cc.
#include "armature/engine/io/gltf/gltf.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "armature/base/utf8.h"
#include "armature/engine/io/gltf/gltf_writer.h"
#include "armature/engine/math/rotation.h"
#include "gltf_importer.h"

namespace armature::gltf_internal {

Status CheckName(const std::string& name, const std::string& where) {
  if (IsValidUtf8(name)) return Status::Ok();
  return Status::InvalidArgument(where + " '" + EscapeForMessage(name) + "' is not valid UTF-8");
}

Status CheckNumbers(const std::vector<double>& v, std::initializer_list<size_t> sizes, const std::string& where) {
  if (std::find(sizes.begin(), sizes.end(), v.size()) == sizes.end())
    return Status::InvalidArgument(where + ": expected " + std::to_string(*(sizes.end() - 1)) + " numbers, got " +
                                   std::to_string(v.size()));
  for (double x : v)
    if (!std::isfinite(x)) return Status::InvalidArgument(where + " is not finite");
  return Status::Ok();
}

namespace {

// A node matrix as T·R·S. Exact for matrices built from TRS; a matrix with
// shear keeps its nearest rotation and is reported.
StatusOr<Trs> DecomposeMatrix(const std::vector<double>& values, const std::string& where,
                              std::vector<std::string>& warnings) {
  const Eigen::Matrix4d m = Eigen::Map<const Eigen::Matrix4d>(values.data());  // column-major, as glTF
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6)
    return Status::InvalidArgument(where + " is not an affine transform (last row is not 0 0 0 1)");
  bool exact = true;
  Trs trs = DecomposeAffine(m, &exact);
  if (!exact) warnings.push_back(where + " has shear or zero scale; decomposed into the nearest rotation and scale");
  return trs;
}

}  // namespace

StatusOr<AssetContents> Importer::Run() {
  // Compressed geometry would read as empty accessors: refuse it plainly.
  for (const std::string& ext : model_.extensionsRequired)
    if (ext == "KHR_draco_mesh_compression" || ext == "EXT_meshopt_compression")
      return Status::InvalidArgument("extensionsRequired: '" + ext + "' (compressed geometry) is not supported");
  if (!model_.nodes.empty()) ARMATURE_RETURN_IF_ERROR(BuildSkeleton());
  instance_.assign(model_.meshes.size(), -1);
  for (size_t i = 0; i < model_.nodes.size(); ++i) {
    const int m = model_.nodes[i].mesh;
    if (m < -1 || m >= static_cast<int>(model_.meshes.size()))
      return Status::InvalidArgument("nodes[" + std::to_string(i) + "].mesh: mesh " + std::to_string(m) +
                                     " does not exist (file has " + std::to_string(model_.meshes.size()) + ")");
    if (m >= 0 && instance_[static_cast<size_t>(m)] < 0) instance_[static_cast<size_t>(m)] = static_cast<int>(i);
  }
  for (size_t m = 0; m < model_.meshes.size(); ++m) ARMATURE_RETURN_IF_ERROR(ImportMesh(m));
  for (size_t a = 0; a < model_.animations.size(); ++a) ARMATURE_RETURN_IF_ERROR(ImportAnimation(a));
  contents_.warnings = std::move(warnings_);
  return std::move(contents_);
}

Status Importer::BuildSkeleton() {
  const size_t n = model_.nodes.size();
  std::vector<int> parent(n, -1);
  for (size_t i = 0; i < n; ++i) {
    for (int c : model_.nodes[i].children) {
      const std::string where = "nodes[" + std::to_string(i) + "].children";
      if (c < 0 || static_cast<size_t>(c) >= n)
        return Status::InvalidArgument(where + ": node " + std::to_string(c) + " does not exist (file has " +
                                       std::to_string(n) + ")");
      if (static_cast<size_t>(c) == i) return Status::InvalidArgument(where + ": a node cannot be its own child");
      if (parent[static_cast<size_t>(c)] >= 0)
        return Status::InvalidArgument(where + ": node " + std::to_string(c) + " already has parent node " +
                                       std::to_string(parent[static_cast<size_t>(c)]));
      parent[static_cast<size_t>(c)] = static_cast<int>(i);
    }
  }
  // Depth-first from each root: parents before children.
  std::vector<size_t> order;
  std::vector<size_t> stack;
  for (size_t root = 0; root < n; ++root) {
    if (parent[root] >= 0) continue;
    stack.push_back(root);
    while (!stack.empty()) {
      const size_t i = stack.back();
      stack.pop_back();
      order.push_back(i);
      const auto& children = model_.nodes[i].children;
      for (auto it = children.rbegin(); it != children.rend(); ++it) stack.push_back(static_cast<size_t>(*it));
    }
  }
  joint_of_.assign(n, -1);
  for (size_t j = 0; j < order.size(); ++j) joint_of_[order[j]] = static_cast<int>(j);
  for (size_t i = 0; i < n; ++i)
    if (joint_of_[i] < 0)
      return Status::InvalidArgument("nodes[" + std::to_string(i) + "]: the node hierarchy has a cycle");

  auto skeleton = std::make_shared<Skeleton>();
  UniqueNames used;
  for (size_t j = 0; j < n; ++j) {
    const size_t i = order[j];
    const tinygltf::Node& node = model_.nodes[i];
    ARMATURE_RETURN_IF_ERROR(CheckName(node.name, "nodes[" + std::to_string(i) + "].name"));
    skeleton->names.push_back(used.Take(node.name.empty() ? "node" + std::to_string(i) : node.name));
    skeleton->parents.push_back(parent[i] < 0 ? -1 : joint_of_[static_cast<size_t>(parent[i])]);
    ARMATURE_ASSIGN_OR_RETURN(auto rest, NodeTrs(node, "nodes[" + std::to_string(i) + "]"));
    skeleton->rest.push_back(rest);
  }
  skeleton->channels.resize(n);
  skeleton->end_sites.resize(n);
  skeleton->units_per_centimetre = UnitsFromExtras();
  ARMATURE_RETURN_IF_ERROR(skeleton->Validate());
  skeleton_ = skeleton;
  contents_.skeletons.push_back({name_, skeleton_});
  return Status::Ok();
}

double Importer::UnitsFromExtras() {
  const tinygltf::Value& extras = model_.asset.extras;
  if (!extras.IsObject() || !extras.Has(kUnitsPerCentimetreExtra)) return 0;
  const tinygltf::Value& value = extras.Get(kUnitsPerCentimetreExtra);
  const double units = value.IsNumber() ? value.GetNumberAsDouble() : 0;
  if (units == 1 || units == 0.01) return units;  // centimetres or metres: the two the unit rule knows
  warnings_.push_back(std::string("asset.extras.") + kUnitsPerCentimetreExtra +
                      ": not 1 or 0.01, ignored (glTF's metres assumed)");
  return 0;
}

StatusOr<Trs> Importer::NodeTrs(const tinygltf::Node& node, const std::string& where) {
  if (!node.matrix.empty()) {
    ARMATURE_RETURN_IF_ERROR(CheckNumbers(node.matrix, {16}, where + ".matrix"));
    return DecomposeMatrix(node.matrix, where + ".matrix", warnings_);
  }
  Trs trs;
  ARMATURE_RETURN_IF_ERROR(CheckNumbers(node.translation, {0, 3}, where + ".translation"));
  ARMATURE_RETURN_IF_ERROR(CheckNumbers(node.rotation, {0, 4}, where + ".rotation"));
  ARMATURE_RETURN_IF_ERROR(CheckNumbers(node.scale, {0, 3}, where + ".scale"));
  if (!node.translation.empty()) trs.translation = Eigen::Vector3d(node.translation.data());
  if (!node.rotation.empty()) {
    const Eigen::Vector4d q(node.rotation.data());  // x, y, z, w
    if (q.norm() < 1e-9) return Status::InvalidArgument(where + ".rotation is a zero quaternion");
    trs.rotation = Eigen::Quaterniond(Eigen::Vector4d(q / q.norm()));
  }
  if (!node.scale.empty()) trs.scale = Eigen::Vector3d(node.scale.data());
  return trs;
}

StatusOr<Importer::SkinBinding> Importer::ReadSkin(int s) {
  const std::string where = "skins[" + std::to_string(s) + "]";
  if (s < 0 || static_cast<size_t>(s) >= model_.skins.size())
    return Status::InvalidArgument(where + " does not exist (file has " + std::to_string(model_.skins.size()) + ")");
  const tinygltf::Skin& skin = model_.skins[static_cast<size_t>(s)];
  SkinBinding b;
  if (skin.joints.empty()) return Status::InvalidArgument(where + ".joints is empty");
  std::set<int> seen;
  for (size_t k = 0; k < skin.joints.size(); ++k) {
    const int node = skin.joints[k];
    if (node < 0 || static_cast<size_t>(node) >= model_.nodes.size())
      return Status::InvalidArgument(where + ".joints[" + std::to_string(k) + "]: node " + std::to_string(node) +
                                     " does not exist (file has " + std::to_string(model_.nodes.size()) + ")");
    if (!seen.insert(node).second)
      return Status::InvalidArgument(where + ".joints[" + std::to_string(k) + "]: node " + std::to_string(node) +
                                     " is listed twice");
    b.joints.push_back(joint_of_[static_cast<size_t>(node)]);
  }
  b.inverse_bind.assign(skin.joints.size(), Eigen::Affine3d::Identity());
  if (skin.inverseBindMatrices >= 0) {
    std::vector<float> m;
    ARMATURE_ASSIGN_OR_RETURN(auto data, reader_.ReadFloats(skin.inverseBindMatrices, where + ".inverseBindMatrices",
                                                            AccessorType::kMat4, {}, &m));
    if (data.count < skin.joints.size())
      return Status::InvalidArgument(where + ".inverseBindMatrices: accessor " +
                                     std::to_string(skin.inverseBindMatrices) + " has " + std::to_string(data.count) +
                                     " matrices for " + std::to_string(skin.joints.size()) + " joints");
    for (size_t k = 0; k < skin.joints.size(); ++k)
      b.inverse_bind[k].matrix() = Eigen::Map<const Eigen::Matrix4f>(m.data() + 16 * k).cast<double>();
  }
  if (skin.skeleton >= 0) {
    if (static_cast<size_t>(skin.skeleton) >= model_.nodes.size())
      return Status::InvalidArgument(where + ".skeleton: node " + std::to_string(skin.skeleton) + " does not exist");
    b.root = joint_of_[static_cast<size_t>(skin.skeleton)];
  }
  return b;
}

}  // namespace armature::gltf_internal

namespace armature {

using gltf_internal::Importer;
using gltf_internal::Load;

StatusOr<AssetContents> ParseGltf(std::string_view bytes, bool binary, std::string_view name,
                                  const ResourceMap& resources, const ImportLimits& limits) {
  ARMATURE_ASSIGN_OR_RETURN(auto model, Load(bytes, binary, resources));
  return Importer(model, name, limits).Run();
}

}  // namespace armature
