// The mesh slice's conversions and checks shared by its unary handlers and its
// stream reactor: skinning method, the clip that poses a mesh, reply sizing.
#pragma once

#include <span>
#include <string>
#include <utility>
#include <vector>

#include "armature/engine/anim/motion.h"
#include "armature/engine/mesh/mesh.h"
#include "armature/engine/mesh/skinning.h"
#include "armature/v1/meshes.pb.h"
#include "armature/v1/motion.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"
#include "server/rpc/reply_size.h"

namespace armature::server {

StatusOr<SkinningMethod> FromProto(v1::SkinningMethod method);

// A clip posing a mesh: a clip of the mesh's skeleton, or of another
// skeleton with the mesh skeleton's joint names (mapped by name).
struct MeshClip {
  PartRef<NamedClip> clip_ref;
  PartRef<NamedSkeleton> skeleton_ref;  // the mesh's, when the clip animates another (else part is null)
  std::vector<int> joint_map;           // then: per joint of the mesh's skeleton, the clip's joint
};

// The clip `name` for `mesh` (any clip for an unbound mesh, which only its
// morph weights track moves). A clip of another skeleton that lacks some of
// the mesh skeleton's joints is INVALID_ARGUMENT naming them.
StatusOr<MeshClip> ClipFor(const Catalog& catalog, const NamedMesh& mesh, const std::string& name);

// Skins `mesh` by `clip` at `time` (SkinClip, onto the mesh's skeleton by the joint map when set).
Status SkinByClip(const Mesh& mesh, const MeshClip& mesh_clip, double time, const SampleOptions& sample,
                  const SkinningOptions& options, std::span<float> positions, std::span<float> normals,
                  SkinningWorkspace& workspace);

// The motion that poses `mesh`, bound: its first layer's clip must animate the
// mesh's skeleton (the other layers map onto it by joint name); errors name
// "motion.layers[i]".
StatusOr<MotionPlan> MotionFor(const Catalog& catalog, const NamedMesh& mesh, const v1::Motion& motion,
                               const Limits& limits);

// Output arrays sized in the response (its only allocation) and viewed as spans.
template <class Response>
std::pair<std::span<float>, std::span<float>> OutputsOf(const Mesh& mesh, Response* response) {
  const int n = static_cast<int>(mesh.vertex_count());
  response->mutable_positions()->Resize(3 * n, 0.f);
  if (!mesh.normals.empty()) response->mutable_normals()->Resize(3 * n, 0.f);
  return {{response->mutable_positions()->mutable_data(), static_cast<size_t>(response->positions_size())},
          {response->mutable_normals()->mutable_data(), static_cast<size_t>(response->normals_size())}};
}

// The bytes of a reply carrying `mesh`'s positions and normals (3 floats per
// vertex each), and with `triangles` its indices (varints), computed before
// any work so an oversized reply is refused naming the flags instead of
// failing in gRPC after the work. The second form looks the mesh up by name
// (OK when it is unknown: the RPC itself reports that).
Status ValidateMeshReply(const Mesh& mesh, bool triangles, const Limits& limits, const std::string& rpc,
                         ReplyEncoding encoding = ReplyEncoding::kProtobuf);
Status ValidateMeshReply(const Catalog& catalog, const std::string& name, bool triangles, const Limits& limits,
                         const std::string& rpc, ReplyEncoding encoding = ReplyEncoding::kProtobuf);

// ValidateMeshReply for one answer carrying every mesh of `meshes` (a character, no triangles).
Status ValidateCharacterReply(const std::vector<const NamedMesh*>& meshes, const Limits& limits, const std::string& rpc,
                              ReplyEncoding encoding = ReplyEncoding::kProtobuf);

}  // namespace armature::server
