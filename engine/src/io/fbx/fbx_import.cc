// FBX import: the Importer's orchestration, its skeleton (assimp's nodes)
// and the units report. Meshes are read in fbx_mesh.cc, animation stacks in
// fbx_animation.cc, the bytes through assimp in fbx_load.cc.
#include "armature/engine/io/fbx/fbx.h"

#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "armature/base/utf8.h"
#include "armature/engine/math/transform.h"
#include "fbx_importer.h"

namespace armature::fbx_internal {

namespace {

// assimp names its root "RootNode"; with an identity transform it adds
// nothing, so the file's own top nodes become the skeleton's roots.
bool IsPlainRoot(const aiNode& node, const aiScene& scene) {
  return &node == scene.mRootNode && node.mTransformation.IsIdentity();
}

// A number of the scene's metadata (assimp stores FBX settings as int32, float or double).
std::optional<double> NumberMeta(const aiMetadata& meta, const char* key) {
  for (unsigned i = 0; i < meta.mNumProperties; ++i) {
    if (std::string_view(meta.mKeys[i].C_Str()) != key || meta.mValues[i].mData == nullptr) continue;
    const void* data = meta.mValues[i].mData;
    switch (meta.mValues[i].mType) {
      case AI_INT32: return *static_cast<const int32_t*>(data);
      case AI_FLOAT: return *static_cast<const float*>(data);
      case AI_DOUBLE: return *static_cast<const double*>(data);
      default: return std::nullopt;
    }
  }
  return std::nullopt;
}

}  // namespace

StatusOr<AssetContents> Importer::Run() {
  ARMATURE_RETURN_IF_ERROR(BuildSkeleton());
  ReportUnits();
  for (unsigned m = 0; m < scene_.mNumMeshes; ++m) ARMATURE_RETURN_IF_ERROR(ImportMesh(m));
  for (unsigned a = 0; a < scene_.mNumAnimations; ++a) ARMATURE_RETURN_IF_ERROR(ImportAnimation(a));
  contents_.warnings = std::move(warnings_);
  return std::move(contents_);
}

Status Importer::BuildSkeleton() {
  auto skeleton = std::make_shared<Skeleton>();
  node_joint_of_mesh_.assign(scene_.mNumMeshes, -1);
  UniqueNames used;
  size_t folded_helpers = 0;
  // Depth-first, parents before children; an explicit stack, as a hostile
  // file may nest deeply. Each entry: the node and its parent's joint.
  std::vector<std::pair<const aiNode*, int>> stack;
  stack.emplace_back(scene_.mRootNode, -1);
  while (!stack.empty()) {
    const auto [node, parent] = stack.back();
    stack.pop_back();
    int joint = parent;
    const std::string name = node->mName.C_Str();
    if (name.find("$AssimpFbx$") != std::string::npos) ++folded_helpers;
    if (!IsPlainRoot(*node, scene_)) {
      if (!IsValidUtf8(name))
        return Status::InvalidArgument("FBX: node name '" + EscapeForMessage(name) + "' is not valid UTF-8");
      bool exact = true;
      const Trs rest = DecomposeAffine(ToEigen(node->mTransformation), &exact);
      if (!exact)
        warnings_.push_back("node '" + EscapeForMessage(name) +
                            "' has shear or zero scale; decomposed into the nearest rotation and scale");
      joint = static_cast<int>(skeleton->names.size());
      skeleton->names.push_back(used.Take(name.empty() ? "node" + std::to_string(joint) : name));
      skeleton->parents.push_back(parent);
      skeleton->rest.push_back(rest);
      joint_of_name_.emplace(name, joint);
      joint_of_node_.emplace(node, joint);
    }
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      const unsigned m = node->mMeshes[k];
      if (m < scene_.mNumMeshes && node_joint_of_mesh_[m] < 0) node_joint_of_mesh_[m] = joint;
    }
    for (unsigned c = node->mNumChildren; c-- > 0;) stack.emplace_back(node->mChildren[c], joint);
  }
  // With pivots folded assimp makes no helper nodes; one would mean a
  // transform this importer has not folded.
  if (folded_helpers > 0)
    warnings_.push_back(std::to_string(folded_helpers) + " assimp pivot helper nodes kept as joints");
  if (skeleton->names.empty()) return Status::Ok();
  skeleton->channels.resize(skeleton->names.size());
  skeleton->end_sites.resize(skeleton->names.size());
  ARMATURE_RETURN_IF_ERROR(skeleton->Validate().WithContext("FBX: "));
  skeleton_ = skeleton;
  contents_.skeletons.push_back({name_, skeleton_});
  return Status::Ok();
}

int Importer::JointNamed(const std::string& node_name) const {
  const auto it = joint_of_name_.find(node_name);
  return it == joint_of_name_.end() ? -1 : it->second;
}

// "FBX units: 1 unit = 1 cm (UnitScaleFactor 1); up axis +Y; kept as the file has them".
void Importer::ReportUnits() {
  const aiMetadata* meta = scene_.mMetaData;
  if (meta == nullptr) return;
  const std::optional<double> unit = NumberMeta(*meta, "UnitScaleFactor");
  const std::optional<double> up = NumberMeta(*meta, "UpAxis");
  const bool has_unit = unit.has_value(), has_up = up && *up >= 0 && *up <= 2;
  const double sign = NumberMeta(*meta, "UpAxisSign").value_or(1);
  if (!has_unit && !has_up) return;
  std::ostringstream line;
  line << "FBX units:";
  if (has_unit) {
    line << " 1 unit = " << *unit << " cm (UnitScaleFactor " << *unit << ")";
    if (std::abs(*unit - 1.0) < 1e-6) line << ", centimetres";
    if (std::abs(*unit - 100.0) < 1e-4) line << ", metres";
  }
  if (has_up) line << (has_unit ? ";" : "") << " up axis " << (sign < 0 ? '-' : '+') << "XYZ"[static_cast<int>(*up)];
  line << "; values kept in the file's units and axes";
  warnings_.push_back(line.str());
}

Status Importer::ChargeDecoded(uint64_t bytes, const std::string& where) {
  return ChargeDecodedBytes(&decoded_bytes_, bytes, limits_, where);
}

}  // namespace armature::fbx_internal

namespace armature {

bool LooksLikeFbx(std::string_view bytes) {
  if (bytes.substr(0, 18) == "Kaydara FBX Binary") return true;
  size_t i = bytes.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;  // a UTF-8 byte order mark
  while (i < bytes.size() && (bytes[i] == ' ' || bytes[i] == '\t' || bytes[i] == '\r' || bytes[i] == '\n')) ++i;
  return bytes.substr(i, 5) == "; FBX";
}

StatusOr<AssetContents> ParseFbx(std::string_view bytes, std::string_view name, const ImportLimits& limits) {
  ARMATURE_RETURN_IF_ERROR(fbx_internal::CheckStructure(bytes, limits));
  ARMATURE_RETURN_IF_ERROR(fbx_internal::TrialRead(bytes, fbx_internal::TrialReadMemory(limits)));
  ARMATURE_ASSIGN_OR_RETURN(auto loaded, fbx_internal::Load(bytes));
  return fbx_internal::Importer(*loaded.scene, name, limits).Run();
}

}  // namespace armature
