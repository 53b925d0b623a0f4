// The FBX importer's state, shared by the files that read its parts:
// fbx_import.cc (nodes → skeleton, units), fbx_mesh.cc (meshes, skins, morph
// targets) and fbx_animation.cc (animation stacks → clips); fbx_load.cc
// runs assimp on the bytes. Private to engine/src/io/fbx.
#pragma once

#include <map>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include "armature/base/unique_names.h"
#include "armature/engine/io/asset.h"
#include "armature/engine/io/import_limits.h"
#include "armature/engine/mesh/mesh.h"

namespace armature::fbx_internal {

// assimp's scene, owned by the importer that read it.
struct LoadedScene {
  std::unique_ptr<Assimp::Importer> importer;
  const aiScene* scene = nullptr;
};

// Runs assimp's FBX reader on `bytes` with every external path refused.
// CheckStructure and TrialRead must have passed them first.
StatusOr<LoadedScene> Load(std::string_view bytes);
// Load in a child process, for its status only: what a failed read leaks
// (libassimp 5.2 does), and a crash or a hang, stay in the child. A read
// that takes over kTrialReadSeconds is killed, and one that needs more
// than `memory_bytes` of address space beyond what the process had is
// RESOURCE_EXHAUSTED (fbx_trial_read.cc). The in-process read that
// follows a good trial allocates as it did, so it stays within them too.
constexpr int kTrialReadSeconds = 120;
// Not in sanitizer builds (the fuzz targets): there libFuzzer bounds
// memory, the child's allocations included (-malloc_limit_mb, which took a
// 3.6 GB reservation for an ASCII array declaring 300 M values).
#if defined(__SANITIZE_ADDRESS__)
#define ARMATURE_FBX_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer)
#define ARMATURE_FBX_SANITIZED 1
#endif
#endif
#if defined(ARMATURE_FBX_SANITIZED)
constexpr bool kTrialReadLimitsMemory = false;
#else
constexpr bool kTrialReadLimitsMemory = true;
#endif
Status TrialRead(std::string_view bytes, uint64_t memory_bytes);
// The memory TrialRead gives assimp: twice max_decoded_bytes, for the
// arrays CheckStructure counted and assimp's copies of them, and at least
// kTrialReadMemoryFloor, for its own structures (a server with little room
// left refuses the import for that room, naming its flag, not here).
constexpr uint64_t kTrialReadMemoryFloor = uint64_t{64} << 20;
uint64_t TrialReadMemory(const ImportLimits& limits);
// INVALID_ARGUMENT when assimp would recurse through the file until the
// stack overflows (its object-to-object connections form a cycle or a
// chain over 1,000 deep, or its scopes nest over 1,000 deep), or when two
// objects share an id (assimp leaks all but the last); RESOURCE_EXHAUSTED
// when a binary file's arrays, inflated, pass limits.max_decoded_bytes.
Status CheckStructure(std::string_view bytes, const ImportLimits& limits);

Eigen::Matrix4d ToEigen(const aiMatrix4x4& m);

class Importer {
 public:
  Importer(const aiScene& scene, std::string_view name, const ImportLimits& limits)
      : scene_(scene), limits_(limits), name_(name) {}

  StatusOr<AssetContents> Run();

 private:
  Status BuildSkeleton();
  void ReportUnits();
  Status ImportMesh(unsigned m);
  Status AddSkin(const aiMesh& am, int node_joint, const std::string& where, Mesh& mesh);
  Status AddMorphTargets(const aiMesh& am, const std::string& where, Mesh& mesh);
  Status ImportAnimation(unsigned a);
  // The joint of an assimp node name (bones and channels name nodes), or -1.
  int JointNamed(const std::string& node_name) const;
  Status ChargeDecoded(uint64_t bytes, const std::string& where);

  const aiScene& scene_;
  const ImportLimits& limits_;
  std::string name_;
  std::shared_ptr<const Skeleton> skeleton_;
  std::map<std::string, int> joint_of_name_;    // assimp node name → joint (the first node of a name)
  std::map<const aiNode*, int> joint_of_node_;  // every kept node → joint
  std::vector<int> node_joint_of_mesh_;         // scene mesh → the joint of the first node showing it, or -1
  UniqueNames used_mesh_names_, used_clip_names_;
  uint64_t decoded_bytes_ = 0;
  AssetContents contents_;
  std::vector<std::string> warnings_;
};

}  // namespace armature::fbx_internal
