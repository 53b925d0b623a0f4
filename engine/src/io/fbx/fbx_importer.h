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
// that takes over kTrialReadSeconds is killed (fbx_trial_read.cc).
constexpr int kTrialReadSeconds = 120;
Status TrialRead(std::string_view bytes);
// INVALID_ARGUMENT when assimp would recurse through the file until the
// stack overflows (its object-to-object connections form a cycle or a
// chain over 1,000 deep, or its scopes nest over 1,000 deep), or when two
// objects share an id (assimp leaks all but the last).
Status CheckStructure(std::string_view bytes);

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
