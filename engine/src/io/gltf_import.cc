#include "armature/engine/io/gltf.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <tiny_gltf.h>

#include "armature/engine/deform/arap.h"
#include "armature/engine/mesh/mesh.h"
#include "armature/base/utf8.h"
#include "gltf_accessor.h"

namespace armature {

namespace {

using gltf_internal::AccessorReader;
using gltf_internal::AccessorType;

constexpr int kUnsignedByte = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
constexpr int kUnsignedShort = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
constexpr int kUnsignedInt = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
constexpr int kByte = TINYGLTF_COMPONENT_TYPE_BYTE;
constexpr int kShort = TINYGLTF_COMPONENT_TYPE_SHORT;

// ---- Loading through tinygltf with the resources map as its file system ----

std::string UrlDecode(std::string_view s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
      out += static_cast<char>(std::stoi(std::string(s.substr(i + 1, 2)), nullptr, 16));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

struct ResourceFiles {
  const ResourceMap* resources;
  std::vector<std::string> missing;

  // tinygltf asks for the url-decoded uri, possibly as "./uri".
  const std::string* Find(std::string path) const {
    if (path.rfind("./", 0) == 0) path = path.substr(2);
    if (auto it = resources->find(path); it != resources->end()) return &it->second;
    for (const auto& [uri, bytes] : *resources)
      if (UrlDecode(uri) == path) return &bytes;
    return nullptr;
  }
};

bool FileExists(const std::string& path, void* user) {
  auto* files = static_cast<ResourceFiles*>(user);
  if (files->Find(path)) return true;
  const std::string name = path.rfind("./", 0) == 0 ? path.substr(2) : path;
  if (std::find(files->missing.begin(), files->missing.end(), name) == files->missing.end())
    files->missing.push_back(name);
  return false;
}

std::string ExpandFilePath(const std::string& path, void*) { return path; }

bool ReadWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  const std::string* bytes = static_cast<ResourceFiles*>(user)->Find(path);
  if (!bytes) {
    if (err) *err += "resource '" + path + "' was not provided";
    return false;
  }
  out->assign(bytes->begin(), bytes->end());
  return true;
}

bool WriteWholeFile(std::string*, const std::string&, const std::vector<unsigned char>&, void*) { return false; }

// Images are not needed for animation and skinning: keep them undecoded.
bool SkipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

std::string Trim(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  return s;
}

uint32_t LittleEndian32(std::string_view bytes, size_t at) {
  uint32_t v = 0;
  for (size_t k = 0; k < 4; ++k) v |= static_cast<uint32_t>(static_cast<unsigned char>(bytes[at + k])) << (8 * k);
  return v;
}

// The GLB container (glTF 2.0, "Binary glTF Layout"): a 12-byte header
// (magic, version, length) and chunks of an 8-byte header (length, type) and
// that many bytes, JSON first, then an optional BIN. tinygltf 2.7.0 trusts
// the BIN chunk's length 8 bytes too far, so every length is checked here
// before it sees the bytes. Returns the `length` bytes the header declares.
StatusOr<std::string_view> CheckGlbContainer(std::string_view bytes) {
  constexpr uint32_t kJson = 0x4E4F534A, kBin = 0x004E4942;
  if (bytes.size() < 20)
    return Status::InvalidArgument("glb: " + std::to_string(bytes.size()) +
                                   " bytes are too few for a header and a JSON chunk (20 bytes at least)");
  if (bytes.substr(0, 4) != "glTF")
    return Status::InvalidArgument("glb: the file does not start with the magic 'glTF' (found '" +
                                   EscapeForMessage(bytes.substr(0, 4)) + "')");
  if (const uint32_t version = LittleEndian32(bytes, 4); version != 2)
    return Status::InvalidArgument("glb: header version " + std::to_string(version) + " is not 2");
  const uint64_t length = LittleEndian32(bytes, 8);
  if (length > bytes.size() || length < 20)
    return Status::InvalidArgument("glb: header length " + std::to_string(length) + " does not fit the file's " +
                                   std::to_string(bytes.size()) + " bytes");
  const uint64_t json_length = LittleEndian32(bytes, 12);
  if (LittleEndian32(bytes, 16) != kJson)
    return Status::InvalidArgument("glb: the first chunk (at byte 12) is not of type JSON");
  const uint64_t json_end = 20 + json_length;
  if (json_length == 0 || json_end > length)
    return Status::InvalidArgument("glb: JSON chunk length " + std::to_string(json_length) + " at byte 12 runs past " +
                                   "the header's length of " + std::to_string(length) + " bytes");
  if (json_end < length) {
    if (json_end + 8 > length)
      return Status::InvalidArgument("glb: " + std::to_string(length - json_end) + " bytes after the JSON chunk (at byte " +
                                     std::to_string(json_end) + ") are too few for a chunk header");
    const uint64_t bin_length = LittleEndian32(bytes, json_end);
    if (LittleEndian32(bytes, json_end + 4) != kBin)
      return Status::InvalidArgument("glb: the second chunk (at byte " + std::to_string(json_end) +
                                     ") is not of type BIN");
    if (json_end + 8 + bin_length > length)
      return Status::InvalidArgument("glb: BIN chunk length " + std::to_string(bin_length) + " at byte " +
                                     std::to_string(json_end) + " runs past the header's length of " +
                                     std::to_string(length) + " bytes");
  }
  return bytes.substr(0, length);
}

StatusOr<tinygltf::Model> Load(std::string_view bytes, bool binary, const ResourceMap& resources) {
  if (bytes.size() > std::numeric_limits<unsigned int>::max())
    return Status::InvalidArgument("glTF: file is larger than 4 GiB");
  if (binary) {
    auto container = CheckGlbContainer(bytes);
    if (!container.ok()) return container.status();
    bytes = *container;
  }
  ResourceFiles files{&resources, {}};
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks({&FileExists, &ExpandFilePath, &ReadWholeFile, &WriteWholeFile, &files});
  loader.SetImageLoader(&SkipImage, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const auto size = static_cast<unsigned int>(bytes.size());
  const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                                       reinterpret_cast<const unsigned char*>(bytes.data()), size, "")
                         : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), size, "");
  if (ok) return model;
  for (const std::string& name : files.missing)
    if (err.find("File not found : " + name) != std::string::npos)
      return Status::InvalidArgument("buffer uri '" + EscapeForMessage(name, 200) +
                                     "' was not provided: pass the file's bytes as a resource keyed by its uri");
  return Status::InvalidArgument("glTF: " + EscapeForMessage(Trim(err.empty() ? warn : err), 400));
}

// ---- Helpers ----

// Names travel in protobuf strings, which must be UTF-8.
Status CheckName(const std::string& name, const std::string& where) {
  if (IsValidUtf8(name)) return Status::Ok();
  return Status::InvalidArgument(where + " '" + EscapeForMessage(name) + "' is not valid UTF-8");
}

std::string Unique(std::string base, std::set<std::string>& used) {
  std::string name = base;
  for (int i = 1; !used.insert(name).second; ++i) name = base + "_" + std::to_string(i);
  return name;
}

Status CheckNumbers(const std::vector<double>& v, std::initializer_list<size_t> sizes, const std::string& where) {
  if (std::find(sizes.begin(), sizes.end(), v.size()) == sizes.end())
    return Status::InvalidArgument(where + ": expected " + std::to_string(*(sizes.end() - 1)) + " numbers, got " +
                                   std::to_string(v.size()));
  for (double x : v)
    if (!std::isfinite(x)) return Status::InvalidArgument(where + " is not finite");
  return Status::Ok();
}

// A node matrix as T·R·S. Exact for matrices built from TRS; a matrix with
// shear keeps its nearest rotation and is reported.
StatusOr<Trs> DecomposeMatrix(const std::vector<double>& values, const std::string& where,
                              std::vector<std::string>& warnings) {
  const Eigen::Matrix4d m = Eigen::Map<const Eigen::Matrix4d>(values.data());  // column-major, as glTF
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6)
    return Status::InvalidArgument(where + " is not an affine transform (last row is not 0 0 0 1)");
  Trs trs;
  trs.translation = m.block<3, 1>(0, 3);
  const Eigen::Matrix3d l = m.topLeftCorner<3, 3>();
  Eigen::Vector3d scale = l.colwise().norm();
  if (l.determinant() < 0) scale.x() = -scale.x();
  Eigen::Matrix3d r = l;
  bool exact = scale.cwiseAbs().minCoeff() > 0;
  if (exact) {
    r = l * scale.cwiseInverse().asDiagonal();
    exact = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-5;
  }
  if (!exact) {
    r = NearestRotation(l.transpose());  // the rotation of the polar decomposition L = R·S
    warnings.push_back(where + " has shear or zero scale; decomposed into the nearest rotation and scale");
  }
  trs.rotation = Eigen::Quaterniond(r).normalized();
  trs.scale = scale;
  return trs;
}

// ---- The importer ----

class Importer {
 public:
  Importer(const tinygltf::Model& model, std::string_view name, const ImportLimits& limits)
      : model_(model), limits_(limits), reader_(model, limits), name_(name) {}

  StatusOr<AssetContents> Run() {
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

 private:
  Status BuildSkeleton() {
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
    std::set<std::string> used;
    for (size_t j = 0; j < n; ++j) {
      const size_t i = order[j];
      const tinygltf::Node& node = model_.nodes[i];
      ARMATURE_RETURN_IF_ERROR(CheckName(node.name, "nodes[" + std::to_string(i) + "].name"));
      skeleton->names.push_back(Unique(node.name.empty() ? "node" + std::to_string(i) : node.name, used));
      skeleton->parents.push_back(parent[i] < 0 ? -1 : joint_of_[static_cast<size_t>(parent[i])]);
      auto rest = NodeTrs(node, "nodes[" + std::to_string(i) + "]");
      if (!rest.ok()) return rest.status();
      skeleton->rest.push_back(*rest);
    }
    skeleton->channels.resize(n);
    skeleton->end_sites.resize(n);
    ARMATURE_RETURN_IF_ERROR(skeleton->Validate());
    skeleton_ = skeleton;
    contents_.skeletons.push_back({name_, skeleton_});
    return Status::Ok();
  }

  StatusOr<Trs> NodeTrs(const tinygltf::Node& node, const std::string& where) {
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

  // ---- Meshes ----

  struct SkinBinding {
    std::vector<int> joints;
    std::vector<Eigen::Affine3d> inverse_bind;
    int root = -1;
  };

  StatusOr<SkinBinding> ReadSkin(int s) {
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
      auto data = reader_.ReadFloats(skin.inverseBindMatrices, where + ".inverseBindMatrices", AccessorType::kMat4,
                                     {}, &m);
      if (!data.ok()) return data.status();
      if (data->count < skin.joints.size())
        return Status::InvalidArgument(where + ".inverseBindMatrices: accessor " +
                                       std::to_string(skin.inverseBindMatrices) + " has " +
                                       std::to_string(data->count) + " matrices for " +
                                       std::to_string(skin.joints.size()) + " joints");
      for (size_t k = 0; k < skin.joints.size(); ++k)
        b.inverse_bind[k].matrix() = Eigen::Map<const Eigen::Matrix4f>(m.data() + 16 * k).cast<double>();
    }
    if (skin.skeleton >= 0) {
      if (static_cast<size_t>(skin.skeleton) >= model_.nodes.size())
        return Status::InvalidArgument(where + ".skeleton: node " + std::to_string(skin.skeleton) +
                                       " does not exist");
      b.root = joint_of_[static_cast<size_t>(skin.skeleton)];
    }
    return b;
  }

  // Per-mesh morph data while primitives are appended: only the vertices a
  // target moves, so memory follows the deltas the file holds.
  struct SparseTarget {
    std::vector<uint32_t> vertices;
    std::vector<Eigen::Vector3f> positions, normals;
    bool has_normals = false;
  };

  Status ImportMesh(size_t m) {
    const tinygltf::Mesh& gm = model_.meshes[m];
    const std::string where = "meshes[" + std::to_string(m) + "]";
    ARMATURE_RETURN_IF_ERROR(CheckName(gm.name, where + ".name"));
    auto mesh = std::make_shared<Mesh>();
    mesh->name = Unique(gm.name.empty() ? std::to_string(m) : gm.name, used_mesh_names_);
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

    std::vector<SparseTarget> targets;
    bool any_normals = false;
    std::vector<std::pair<size_t, size_t>> missing_normals;  // vertex ranges of primitives without NORMAL
    size_t zero_weight_vertices = 0;
    for (size_t p = 0; p < gm.primitives.size(); ++p) {
      ARMATURE_RETURN_IF_ERROR(AppendPrimitive(gm.primitives[p], where + ".primitives[" + std::to_string(p) + "]",
                                               p == 0, skin, *mesh, targets, any_normals, missing_normals,
                                               zero_weight_vertices));
    }
    if (!any_normals) mesh->normals.clear();
    if (any_normals && !missing_normals.empty()) {
      // A primitive's triangles only reference its own vertices, so the whole
      // mesh's vertex normals are each primitive's own.
      const auto computed = ComputeVertexNormals(mesh->positions, mesh->triangles);
      for (const auto& [begin, end] : missing_normals)
        std::copy(computed.begin() + static_cast<ptrdiff_t>(begin), computed.begin() + static_cast<ptrdiff_t>(end),
                  mesh->normals.begin() + static_cast<ptrdiff_t>(begin));
      warnings_.push_back(where + ": some primitives have no NORMAL; computed from their triangles");
    }
    if (zero_weight_vertices > 0)
      warnings_.push_back(where + ": " + std::to_string(zero_weight_vertices) +
                          " vertices have all-zero weights; bound to their first listed joint");

    // Morph targets: sparse deltas, names, default weights (the node's override the mesh's).
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
      if (targets[t].has_normals && any_normals) target.normal_deltas = std::move(targets[t].normals);
      mesh->targets.push_back(std::move(target));
    }
    std::vector<double> weights = gm.weights;
    if (node >= 0 && !model_.nodes[static_cast<size_t>(node)].weights.empty())
      weights = model_.nodes[static_cast<size_t>(node)].weights;
    if (!weights.empty() && weights.size() != targets.size())
      return Status::InvalidArgument(where + ".weights: " + std::to_string(weights.size()) + " weights for " +
                                     std::to_string(targets.size()) + " morph targets");
    mesh->default_weights.assign(targets.size(), 0.f);
    for (size_t t = 0; t < weights.size(); ++t) {
      if (!std::isfinite(weights[t])) return Status::InvalidArgument(where + ".weights is not finite");
      mesh->default_weights[t] = static_cast<float>(weights[t]);
    }

    std::vector<std::string> mesh_warnings;
    ARMATURE_RETURN_IF_ERROR(FinalizeMesh(*mesh, &mesh_warnings).WithContext(where + ": "));
    for (const std::string& w : mesh_warnings) warnings_.push_back(where + ": " + w);
    contents_.meshes.push_back({name_ + "." + mesh->name, node >= 0 ? name_ : "", mesh});
    return Status::Ok();
  }

  Status AppendPrimitive(const tinygltf::Primitive& prim, const std::string& where, bool first, int skin, Mesh& mesh,
                         std::vector<SparseTarget>& targets, bool& any_normals,
                         std::vector<std::pair<size_t, size_t>>& missing_normals,
                         size_t& zero_weight_vertices) {
    const size_t base = mesh.positions.size();
    auto attribute = [&](const char* semantic) {
      auto it = prim.attributes.find(semantic);
      return it == prim.attributes.end() ? -1 : it->second;
    };
    const std::string attrs = where + ".attributes.";
    const int position_accessor = attribute("POSITION");
    if (position_accessor < 0) return Status::InvalidArgument(where + ".attributes has no POSITION");
    // Sizes before decoding: the mesh's vertices, and morph targets × vertices.
    auto declared = reader_.Count(position_accessor, attrs + "POSITION");
    if (!declared.ok()) return declared.status();
    const uint64_t vertices = static_cast<uint64_t>(base) + std::min<uint64_t>(*declared, UINT64_MAX / 2);
    if (vertices > limits_.max_mesh_vertices)
      return Status::ResourceExhausted(attrs + "POSITION: " + OverImportLimitCount(vertices, "vertices", "max_mesh_vertices",
                                                                                   limits_.max_mesh_vertices));
    uint64_t morph = 0;
    if (__builtin_mul_overflow(vertices, prim.targets.size(), &morph)) morph = UINT64_MAX;
    if (morph > limits_.max_morph_target_vertices)
      return Status::ResourceExhausted(where + ".targets: " +
                                       OverImportLimit(std::to_string(prim.targets.size()) + " morph targets × " +
                                                           std::to_string(vertices) + " vertices =",
                                                       morph, "max_morph_target_vertices",
                                                       limits_.max_morph_target_vertices));
    std::vector<float> positions;
    auto pos = reader_.ReadFloats(position_accessor, attrs + "POSITION", AccessorType::kVec3, {}, &positions);
    if (!pos.ok()) return pos.status();
    const size_t count = pos->count;
    auto check_count = [&](const gltf_internal::AccessorData& d, const std::string& field, int accessor) -> Status {
      if (d.count != count)
        return Status::InvalidArgument(field + ": accessor " + std::to_string(accessor) + " has " +
                                       std::to_string(d.count) + " elements, POSITION has " + std::to_string(count));
      return Status::Ok();
    };
    for (size_t v = 0; v < count; ++v)
      mesh.positions.emplace_back(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);

    // Triangles.
    std::vector<uint32_t> indices;
    if (prim.indices >= 0) {
      auto idx = reader_.ReadUints(prim.indices, where + ".indices", AccessorType::kScalar,
                                   {kUnsignedByte, kUnsignedShort, kUnsignedInt}, &indices);
      if (!idx.ok()) return idx.status();
      for (size_t i = 0; i < indices.size(); ++i)
        if (indices[i] >= count)
          return Status::InvalidArgument(where + ".indices: accessor " + std::to_string(prim.indices) + " element " +
                                         std::to_string(i) + " = " + std::to_string(indices[i]) +
                                         " is out of range (" + std::to_string(count) + " vertices)");
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

    // Normals.
    const int normal_accessor = attribute("NORMAL");
    if (normal_accessor >= 0) {
      std::vector<float> normals;
      auto nrm = reader_.ReadFloats(normal_accessor, attrs + "NORMAL", AccessorType::kVec3, {}, &normals);
      if (!nrm.ok()) return nrm.status();
      ARMATURE_RETURN_IF_ERROR(check_count(*nrm, attrs + "NORMAL", normal_accessor));
      mesh.normals.resize(base);
      for (size_t v = 0; v < count; ++v) mesh.normals.emplace_back(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]);
      any_normals = true;
    } else {
      // Computed from the triangles once all primitives are in, if another
      // primitive has NORMAL.
      missing_normals.emplace_back(base, base + count);
      mesh.normals.resize(base + count, Eigen::Vector3f::Zero());
    }

    // Skin influences: every JOINTS_n/WEIGHTS_n pair.
    if (skin >= 0) {
      const size_t joint_count = model_.skins[static_cast<size_t>(skin)].joints.size();
      std::vector<std::vector<uint32_t>> joint_sets;
      std::vector<std::vector<float>> weight_sets;
      for (int set = 0;; ++set) {
        const std::string js = "JOINTS_" + std::to_string(set), ws = "WEIGHTS_" + std::to_string(set);
        const int ja = attribute(js.c_str()), wa = attribute(ws.c_str());
        if (ja < 0 && wa < 0) break;
        if (ja < 0 || wa < 0)
          return Status::InvalidArgument(attrs + (ja < 0 ? ws : js) + " has no matching " + (ja < 0 ? js : ws));
        joint_sets.emplace_back();
        weight_sets.emplace_back();
        auto jd = reader_.ReadUints(ja, attrs + js, AccessorType::kVec4, {kUnsignedByte, kUnsignedShort},
                                    &joint_sets.back());
        if (!jd.ok()) return jd.status();
        ARMATURE_RETURN_IF_ERROR(check_count(*jd, attrs + js, ja));
        auto wd = reader_.ReadFloats(wa, attrs + ws, AccessorType::kVec4, {kUnsignedByte, kUnsignedShort},
                                     &weight_sets.back());
        if (!wd.ok()) return wd.status();
        ARMATURE_RETURN_IF_ERROR(check_count(*wd, attrs + ws, wa));
        for (size_t i = 0; i < joint_sets.back().size(); ++i) {
          const float w = weight_sets.back()[i];
          if (w < 0)
            return Status::InvalidArgument(attrs + ws + ": accessor " + std::to_string(wa) + " element " +
                                           std::to_string(i / 4) + " has a negative weight");
          if (w > 0 && joint_sets.back()[i] >= joint_count)
            return Status::InvalidArgument(attrs + js + ": accessor " + std::to_string(ja) + " element " +
                                           std::to_string(i / 4) + " uses joint " +
                                           std::to_string(joint_sets.back()[i]) + " but skin " +
                                           std::to_string(skin) + " has " + std::to_string(joint_count) + " joints");
        }
      }
      if (joint_sets.empty())
        return Status::InvalidArgument(where + ": the node's skin " + std::to_string(skin) +
                                       " needs JOINTS_0 and WEIGHTS_0 attributes");
      if (mesh.influence_offsets.empty()) mesh.influence_offsets.push_back(0);
      for (size_t v = 0; v < count; ++v) {
        const size_t before = mesh.influence_joints.size();
        for (size_t s = 0; s < joint_sets.size(); ++s)
          for (size_t c = 0; c < 4; ++c)
            if (weight_sets[s][4 * v + c] > 0) {
              mesh.influence_joints.push_back(joint_sets[s][4 * v + c]);
              mesh.influence_weights.push_back(weight_sets[s][4 * v + c]);
            }
        if (mesh.influence_joints.size() == before) {
          // As three.js's normalizeSkinWeights: all weight on the first listed joint.
          ++zero_weight_vertices;
          const uint32_t j = joint_sets[0][4 * v];
          if (j >= joint_count)
            return Status::InvalidArgument(attrs + "JOINTS_0: element " + std::to_string(v) + " uses joint " +
                                           std::to_string(j) + " but skin " + std::to_string(skin) + " has " +
                                           std::to_string(joint_count) + " joints");
          mesh.influence_joints.push_back(j);
          mesh.influence_weights.push_back(1.f);
        }
        mesh.influence_offsets.push_back(static_cast<uint32_t>(mesh.influence_joints.size()));
      }
    } else if (!mesh.joints.empty()) {
      if (attribute("JOINTS_0") >= 0) warnings_.push_back(where + ": JOINTS_0 without a skin on the node; ignored");
      if (mesh.influence_offsets.empty()) mesh.influence_offsets.push_back(0);
      for (size_t v = 0; v < count; ++v) {
        mesh.influence_joints.push_back(0);
        mesh.influence_weights.push_back(1.f);
        mesh.influence_offsets.push_back(static_cast<uint32_t>(mesh.influence_joints.size()));
      }
    }

    // Morph targets.
    if (first) targets.resize(prim.targets.size());
    if (prim.targets.size() != targets.size())
      return Status::InvalidArgument(where + ".targets: " + std::to_string(prim.targets.size()) +
                                     " targets, the first primitive has " + std::to_string(targets.size()));
    for (size_t t = 0; t < targets.size(); ++t) {
      SparseTarget& sparse = targets[t];
      const std::string twhere = where + ".targets[" + std::to_string(t) + "].";
      std::vector<float> deltas[2];  // POSITION, NORMAL; empty when the target has none
      for (int k = 0; k < 2; ++k) {
        const char* semantic = k == 0 ? "POSITION" : "NORMAL";
        auto it = prim.targets[t].find(semantic);
        if (it == prim.targets[t].end()) continue;
        auto d = reader_.ReadFloats(it->second, twhere + semantic, AccessorType::kVec3, {}, &deltas[k]);
        if (!d.ok()) return d.status();
        ARMATURE_RETURN_IF_ERROR(check_count(*d, twhere + semantic, it->second));
        if (k == 1) sparse.has_normals = true;
      }
      auto delta = [&](int k, size_t v) {
        return deltas[k].empty() ? Eigen::Vector3f::Zero().eval()
                                 : Eigen::Vector3f(deltas[k][3 * v], deltas[k][3 * v + 1], deltas[k][3 * v + 2]);
      };
      for (size_t v = 0; v < count; ++v) {
        const Eigen::Vector3f p = delta(0, v), n = delta(1, v);
        if (p.isZero(0) && n.isZero(0)) continue;
        sparse.vertices.push_back(static_cast<uint32_t>(base + v));
        sparse.positions.push_back(p);
        sparse.normals.push_back(n);
      }
    }
    return Status::Ok();
  }

  // ---- Animations ----

  // glTF mesh `m` as imported: ImportMesh appends one entry per mesh, in
  // order, or fails the import, and all meshes are imported before animations.
  const Mesh& ImportedMesh(int m) const { return *contents_.meshes[static_cast<size_t>(m)].mesh; }

  Status ImportAnimation(size_t a) {
    const tinygltf::Animation& anim = model_.animations[a];
    const std::string where = "animations[" + std::to_string(a) + "]";
    if (!skeleton_) return Status::InvalidArgument(where + ": the file has no nodes to animate");
    auto clip = std::make_shared<Clip>();
    clip_keys_ = 0;
    clip->skeleton = skeleton_;
    clip->joints.resize(skeleton_->size());
    clip->default_interpolation = Interpolation::kLinear;
    std::set<std::pair<int, std::string>> animated;
    for (size_t c = 0; c < anim.channels.size(); ++c) {
      const tinygltf::AnimationChannel& channel = anim.channels[c];
      const std::string cwhere = where + ".channels[" + std::to_string(c) + "]";
      if (channel.target_node < 0) {
        warnings_.push_back(cwhere + " has no target node; ignored");
        continue;
      }
      if (static_cast<size_t>(channel.target_node) >= model_.nodes.size())
        return Status::InvalidArgument(cwhere + ".target.node: node " + std::to_string(channel.target_node) +
                                       " does not exist (file has " + std::to_string(model_.nodes.size()) + ")");
      const std::string& path = channel.target_path;
      if (path != "translation" && path != "rotation" && path != "scale" && path != "weights") {
        warnings_.push_back(cwhere + ".target.path '" + path + "' is not supported; ignored");
        continue;
      }
      if (channel.sampler < 0 || static_cast<size_t>(channel.sampler) >= anim.samplers.size())
        return Status::InvalidArgument(cwhere + ".sampler: sampler " + std::to_string(channel.sampler) +
                                       " does not exist (animation has " + std::to_string(anim.samplers.size()) + ")");
      if (!animated.insert({channel.target_node, path}).second)
        warnings_.push_back(cwhere + " animates node " + std::to_string(channel.target_node) + " " + path +
                            " again; the later channel wins");
      ARMATURE_RETURN_IF_ERROR(ImportChannel(anim, channel, where + ".samplers[" + std::to_string(channel.sampler) + "]",
                                             *clip));
    }
    ARMATURE_RETURN_IF_ERROR(clip->Validate().WithContext(where + ": "));
    ARMATURE_RETURN_IF_ERROR(CheckName(anim.name, where + ".name"));
    const std::string local = Unique(anim.name.empty() ? std::to_string(a) : anim.name, used_clip_names_);
    contents_.clips.push_back({name_ + "." + local, name_, clip});
    return Status::Ok();
  }

  Status ImportChannel(const tinygltf::Animation& anim, const tinygltf::AnimationChannel& channel,
                       const std::string& swhere, Clip& clip) {
    const tinygltf::AnimationSampler& sampler = anim.samplers[static_cast<size_t>(channel.sampler)];
    Interpolation interpolation;
    if (sampler.interpolation == "LINEAR" || sampler.interpolation.empty()) interpolation = Interpolation::kLinear;
    else if (sampler.interpolation == "STEP") interpolation = Interpolation::kStep;
    else if (sampler.interpolation == "CUBICSPLINE") interpolation = Interpolation::kCubic;
    else
      return Status::InvalidArgument(swhere + ".interpolation '" + sampler.interpolation +
                                     "' is not LINEAR, STEP or CUBICSPLINE");
    const bool cubic = interpolation == Interpolation::kCubic;

    // Keys before decoding: per sampler, and summed over the clip's tracks.
    auto declared = reader_.Count(sampler.input, swhere + ".input");
    if (!declared.ok()) return declared.status();
    if (*declared > limits_.max_clip_frames)
      return Status::ResourceExhausted(swhere + ".input: accessor " + std::to_string(sampler.input) + ": " +
                                       OverImportLimit("key count", *declared, "max_clip_frames",
                                                       limits_.max_clip_frames));
    if (__builtin_add_overflow(clip_keys_, *declared, &clip_keys_)) clip_keys_ = UINT64_MAX;
    if (clip_keys_ > limits_.max_clip_keys)
      return Status::ResourceExhausted(swhere + ".input: " + OverImportLimit("keys of the clip's tracks", clip_keys_,
                                                                             "max_clip_keys", limits_.max_clip_keys));
    std::vector<float> input;
    auto in = reader_.ReadFloats(sampler.input, swhere + ".input", AccessorType::kScalar, {}, &input);
    if (!in.ok()) return in.status();
    std::vector<double> times(input.begin(), input.end());
    for (size_t k = 1; k < times.size(); ++k)
      if (!(times[k] > times[k - 1]))
        return Status::InvalidArgument(swhere + ".input: accessor " + std::to_string(sampler.input) + " key " +
                                       std::to_string(k) + " time " + std::to_string(times[k]) +
                                       " does not increase");
    const size_t keys = times.size();

    const std::string& path = channel.target_path;
    const size_t node = static_cast<size_t>(channel.target_node);
    size_t per_key = cubic ? 3 : 1;
    AccessorType type = AccessorType::kVec3;
    std::initializer_list<int> normalized = {};
    static constexpr std::initializer_list<int> kNormalizedInts = {kByte, kUnsignedByte, kShort, kUnsignedShort};
    int mesh = -1;
    if (path == "rotation") {
      type = AccessorType::kVec4;
      normalized = kNormalizedInts;
    } else if (path == "weights") {
      type = AccessorType::kScalar;
      normalized = kNormalizedInts;
      mesh = model_.nodes[node].mesh;
      if (mesh < 0)
        return Status::InvalidArgument(swhere + ": weights channel targets node " + std::to_string(node) +
                                       ", which has no mesh");
      if (instance_[static_cast<size_t>(mesh)] != static_cast<int>(node)) {
        warnings_.push_back(swhere + ": weights of a second instance of mesh " + std::to_string(mesh) + "; ignored");
        return Status::Ok();
      }
      per_key *= ImportedMesh(mesh).targets.size();
    }
    std::vector<float> output;
    auto out = reader_.ReadFloats(sampler.output, swhere + ".output", type, normalized, &output);
    if (!out.ok()) return out.status();
    if (out->count != keys * per_key)
      return Status::InvalidArgument(swhere + ".output: accessor " + std::to_string(sampler.output) + " has " +
                                     std::to_string(out->count) + " elements, expected " +
                                     std::to_string(keys * per_key) + " (" + std::to_string(keys) + " keys" +
                                     (cubic ? " × 3 for CUBICSPLINE" : "") +
                                     (mesh >= 0 ? " × " + std::to_string(ImportedMesh(mesh).targets.size()) + " targets"
                                                : std::string()) +
                                     ")");
    clip.duration = std::max(clip.duration, times.back());
    clip.frame_count = std::max(clip.frame_count, keys);

    if (mesh >= 0) {
      WeightsTrack track;
      track.mesh = ImportedMesh(mesh).name;
      track.targets = ImportedMesh(mesh).targets.size();
      track.times = times;
      track.values.assign(output.begin(), output.end());
      track.interpolation = interpolation;
      auto same = std::find_if(clip.weights.begin(), clip.weights.end(),
                               [&](const WeightsTrack& w) { return w.mesh == track.mesh; });
      if (same != clip.weights.end()) *same = std::move(track);
      else clip.weights.push_back(std::move(track));
      return Status::Ok();
    }

    JointTrack& joint = clip.joints[static_cast<size_t>(joint_of_[node])];
    // Element e of key k: CUBICSPLINE stores (in-tangent, value, out-tangent) per key.
    auto element = [&](size_t k, size_t part) { return output.data() + (k * (cubic ? 3 : 1) + part) * out->components; };
    if (path == "rotation") {
      QuatTrack& track = joint.rotation;
      track = QuatTrack{};
      track.times = times;
      track.interpolation = interpolation;
      auto quat = [](const float* p) { return Eigen::Quaterniond(p[3], p[0], p[1], p[2]); };
      for (size_t k = 0; k < keys; ++k) {
        Eigen::Quaterniond q = quat(element(k, cubic ? 1 : 0));
        if (q.norm() < 1e-6)
          return Status::InvalidArgument(swhere + ".output: accessor " + std::to_string(sampler.output) + " key " +
                                         std::to_string(k) + " is a zero quaternion");
        track.values.push_back(q.normalized());
        if (cubic) {
          track.in_tangents.push_back(quat(element(k, 0)));
          track.out_tangents.push_back(quat(element(k, 2)));
        }
      }
    } else {
      Vec3Track& track = path == "translation" ? joint.translation : joint.scale;
      track = Vec3Track{};
      track.times = times;
      track.interpolation = interpolation;
      auto vec = [](const float* p) { return Eigen::Vector3d(p[0], p[1], p[2]); };
      for (size_t k = 0; k < keys; ++k) {
        track.values.push_back(vec(element(k, cubic ? 1 : 0)));
        if (cubic) {
          track.in_tangents.push_back(vec(element(k, 0)));
          track.out_tangents.push_back(vec(element(k, 2)));
        }
      }
    }
    return Status::Ok();
  }

  const tinygltf::Model& model_;
  const ImportLimits& limits_;
  AccessorReader reader_;
  std::string name_;
  AssetContents contents_;
  std::vector<std::string> warnings_;
  std::shared_ptr<const Skeleton> skeleton_;
  std::vector<int> joint_of_;            // node → skeleton joint
  std::vector<int> instance_;            // mesh → first node using it, or -1
  std::set<std::string> used_mesh_names_, used_clip_names_;
  uint64_t clip_keys_ = 0;  // keys of the clip being imported, all tracks
};

}  // namespace

StatusOr<AssetContents> ParseGltf(std::string_view bytes, bool binary, std::string_view name,
                                  const ResourceMap& resources, const ImportLimits& limits) {
  auto model = Load(bytes, binary, resources);
  if (!model.ok()) return model.status();
  return Importer(*model, name, limits).Run();
}

}  // namespace armature
