// The glTF importer's state, shared by the files that read its parts:
// gltf_import.cc (nodes, skins → skeleton), gltf_mesh.cc (meshes, skin
// influences, morph targets) and gltf_animation.cc (samplers → clip tracks).
// Private to engine/src/io/gltf.
#pragma once

#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <tiny_gltf.h>

#include "armature/base/unique_names.h"
#include "armature/engine/io/asset.h"
#include "armature/engine/io/import_limits.h"
#include "armature/engine/mesh/material.h"
#include "armature/engine/mesh/mesh.h"
#include "gltf_accessor.h"

namespace armature::gltf_internal {

constexpr int kUnsignedByte = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
constexpr int kUnsignedShort = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
constexpr int kUnsignedInt = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
constexpr int kByte = TINYGLTF_COMPONENT_TYPE_BYTE;
constexpr int kShort = TINYGLTF_COMPONENT_TYPE_SHORT;

// Names travel in protobuf strings, which must be UTF-8.
Status CheckName(const std::string& name, const std::string& where);
Status CheckNumbers(const std::vector<double>& v, std::initializer_list<size_t> sizes, const std::string& where);

// Parses the glTF JSON (or GLB container), reading external buffers from `resources`.
StatusOr<tinygltf::Model> Load(std::string_view bytes, bool binary, const ResourceMap& resources);

class Importer {
 public:
  Importer(const tinygltf::Model& model, std::string_view name, const ImportLimits& limits)
      : model_(model), limits_(limits), reader_(model, limits), name_(name) {}

  StatusOr<AssetContents> Run();

 private:
  struct SkinBinding {
    std::vector<int> joints;
    std::vector<Eigen::Affine3d> inverse_bind;
    int root = -1;
  };
  // Per-mesh morph data while primitives are appended: only the vertices a
  // target moves, so memory follows the deltas the file holds.
  struct SparseTarget {
    std::vector<uint32_t> vertices;
    std::vector<Eigen::Vector3f> positions, normals;
    bool has_normals = false;
  };
  Status BuildSkeleton();
  StatusOr<Trs> NodeTrs(const tinygltf::Node& node, const std::string& where);
  double UnitsFromExtras();  // Skeleton::units_per_centimetre from asset.extras, or 0
  StatusOr<SkinBinding> ReadSkin(int s);
  Status ImportMesh(size_t m);
  // What a mesh's primitives gather while appended, for ImportMesh to finish.
  struct MeshInProgress {
    std::vector<SparseTarget> targets;
    bool any_normals = false;
    std::vector<std::pair<size_t, size_t>> missing_normals;  // vertex ranges of primitives without NORMAL
    size_t zero_weight_vertices = 0;
  };
  // The primitive being appended: its vertices are the mesh's [base, base + count).
  struct PrimitiveSlot {
    const tinygltf::Primitive& prim;
    std::string where;  // "meshes[m].primitives[p]"
    std::string attrs;  // where + ".attributes."
    size_t base = 0;
    size_t count = 0;
  };
  // A skinned primitive's JOINTS_n and WEIGHTS_n, four per vertex per set.
  struct InfluenceSets {
    std::vector<std::vector<uint32_t>> joints;
    std::vector<std::vector<float>> weights;
  };
  Status AppendPrimitive(const tinygltf::Primitive& prim, const std::string& where, bool first, int skin, Mesh& mesh,
                         MeshInProgress& progress);
  // Checks the sizes against the limits, charges the primitive and appends its
  // positions; sets slot.count.
  Status AppendPositions(PrimitiveSlot& slot, int skin, Mesh& mesh);
  Status AppendTriangles(const PrimitiveSlot& slot, Mesh& mesh);
  Status AppendNormals(const PrimitiveSlot& slot, Mesh& mesh, MeshInProgress& progress);
  StatusOr<InfluenceSets> ReadInfluenceSets(const PrimitiveSlot& slot, int skin);
  Status AppendInfluences(const PrimitiveSlot& slot, int skin, Mesh& mesh, size_t& zero_weight_vertices);
  Status AppendMorphTargets(const PrimitiveSlot& slot, bool first, std::vector<SparseTarget>& targets);
  // The gathered targets into `mesh`, named, with their default weights.
  Status AddMorphTargets(const tinygltf::Mesh& gm, int node, const std::string& where, MeshInProgress& progress,
                         Mesh& mesh);
  // glTF mesh `m` as imported: ImportMesh appends one entry per mesh, in
  // order, or fails the import, and all meshes are imported before animations.
  const Mesh& ImportedMesh(int m) const { return *contents_.meshes[static_cast<size_t>(m)].mesh; }
  // Adds `bytes` to the import's estimated decoded size: RESOURCE_EXHAUSTED
  // naming `where` and max_decoded_bytes once the sum passes it.
  Status ChargeDecoded(uint64_t bytes, const std::string& where);
  // Charges what a primitive of `vertices` vertices will build, before it is decoded.
  Status ChargePrimitive(const tinygltf::Primitive& prim, const std::string& where, uint64_t vertices, int skin);
  // Materials and images, each built once per file and shared by the meshes
  // using it (gltf_material.cc); null when the file's image is unusable (a
  // warning says why).
  StatusOr<std::shared_ptr<const Material>> MaterialOf(int index);
  StatusOr<std::shared_ptr<const MaterialImage>> ImageOf(int index);
  StatusOr<TextureRef> ReadTexture(int texture, int texcoord, double scale, const std::string& where,
                                   std::vector<std::shared_ptr<const MaterialImage>>& images);
  // TEXCOORD_0 of a primitive's `count` vertices from `base` (zeros without it).
  Status AppendTexcoords(const tinygltf::Primitive& prim, const std::string& attrs, size_t base, size_t count,
                         Mesh& mesh);
  void FinishUvsAndMaterials(const tinygltf::Mesh& gm, const std::string& where, Mesh& mesh);
  Status AddMaterialGroup(const tinygltf::Primitive& prim, const std::string& where, size_t first_triangle, Mesh& mesh);
  Status ImportAnimation(size_t a);
  StatusOr<std::vector<double>> ReadKeyTimes(const tinygltf::AnimationSampler& sampler, const std::string& swhere);
  Status ImportChannel(const tinygltf::Animation& anim, const tinygltf::AnimationChannel& channel,
                       const std::string& swhere, Clip& clip);

  const tinygltf::Model& model_;
  const ImportLimits& limits_;
  AccessorReader reader_;
  std::string name_;
  AssetContents contents_;
  std::vector<std::string> warnings_;
  std::shared_ptr<const Skeleton> skeleton_;
  std::vector<int> joint_of_;  // node → skeleton joint
  std::vector<int> instance_;  // mesh → first node using it, or -1
  UniqueNames used_mesh_names_, used_clip_names_;
  std::vector<std::shared_ptr<const Material>> materials_;  // by glTF index, built on first use
  std::vector<std::shared_ptr<const MaterialImage>> images_;
  uint64_t clip_keys_ = 0;      // keys of the clip being imported, all tracks
  uint64_t decoded_bytes_ = 0;  // estimated memory of everything decoded so far (ChargeDecoded)
};

}  // namespace armature::gltf_internal
