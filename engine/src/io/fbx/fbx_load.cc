// assimp's FBX reader on bytes in memory. The file may name textures and
// other files; the IO system refuses every path, so nothing outside the bytes
// is ever opened.
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>

#include <stdexcept>
#include <string>

#include "armature/base/utf8.h"
#include "fbx_importer.h"

// Debian's libassimp is built with its internal checks on, and a failed one
// (aiAssertViolation) aborted the process: a 497-byte binary FBX whose
// record length runs past the file failed `begin <= cursor` in the
// tokenizer. libassimp calls the handler through its PLT, so this
// definition in the program replaces its own, and the failure becomes an
// import error: BaseImporter::ReadFile catches it, the read returns no
// scene, and Load answers INVALID_ARGUMENT with the check in the message.
// assimp's own errors are std::runtime_errors thrown the same way, so it
// unwinds as they do.
namespace Assimp {
void aiAssertViolation(const char* failed_expression, const char* file, int line) {
  const char* base = file;
  for (const char* c = file; *c != '\0'; ++c)
    if (*c == '/') base = c + 1;
  throw std::runtime_error(std::string("assimp's check ") + failed_expression + " failed (" + base + ":" +
                           std::to_string(line) + ")");
}
}  // namespace Assimp

namespace armature::fbx_internal {

namespace {

class RefusingIoSystem : public Assimp::IOSystem {
 public:
  bool Exists(const char*) const override { return false; }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char*, const char*) override { return nullptr; }
  void Close(Assimp::IOStream* stream) override { delete stream; }
};

}  // namespace

Eigen::Matrix4d ToEigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d r;
  r << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4;
  return r;
}

StatusOr<LoadedScene> Load(std::string_view bytes) {
  if (bytes.empty()) return Status::InvalidArgument("FBX: the file is empty");
  LoadedScene loaded;
  loaded.importer = std::make_unique<Assimp::Importer>();
  Assimp::Importer& importer = *loaded.importer;
  importer.SetIOHandler(new RefusingIoSystem);  // the importer owns it
  // Pivots, pre- and post-rotations folded into each node (and baked into its
  // animation) instead of assimp's "$AssimpFbx$" helper nodes.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_TEXTURES, false);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_CAMERAS, false);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_LIGHTS, false);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_STRICT_MODE, false);
  constexpr unsigned kSteps = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_ValidateDataStructure;
  const aiScene* scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), kSteps, "fbx");
  if (scene == nullptr) {
    const std::string error = importer.GetErrorString();
    return Status::InvalidArgument(
        "FBX: " + (error.empty() ? std::string("assimp could not read the file") : EscapeForMessage(error, 300)));
  }
  if (scene->mRootNode == nullptr) return Status::InvalidArgument("FBX: the scene has no root node");
  // assimp marks a scene without meshes incomplete; a rig and its animation
  // (Mixamo's "without skin" download) is a whole file here.
  if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) && scene->mRootNode->mNumChildren == 0 && scene->mNumAnimations == 0)
    return Status::InvalidArgument("FBX: assimp read an incomplete scene (no nodes, meshes or animations)");
  loaded.scene = scene;
  return loaded;
}

}  // namespace armature::fbx_internal
