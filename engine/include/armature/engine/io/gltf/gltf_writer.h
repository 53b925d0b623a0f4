// glTF 2.0 export (via tinygltf's writer), to memory only: a clip, its
// skeleton and optionally the meshes skinned to that skeleton.
//
// The skeleton becomes nodes in joint order (node i = joint i; rest TRS,
// children, the roots in the scene). The clip becomes one animation with a
// rotation, translation and scale channel per animated joint: LINEAR and STEP
// tracks keep their keys and interpolation, CUBIC tracks with glTF tangents
// become CUBICSPLINE samplers, CUBIC tracks without tangents (Catmull-Rom,
// squad: not expressible in glTF) are written LINEAR at their keys and in
// between at the clip's frame rate (1/30 s when it has none). A BVH clip's
// tracks are keyed at its frames, so it is written LINEAR at its frame times.
// Each mesh becomes a glTF mesh (POSITION, NORMAL, indices, JOINTS_n and
// WEIGHTS_n, morph targets with POSITION and NORMAL deltas, default weights,
// target names in extras.targetNames) with a skin (joints, inverse bind
// matrices) on a node of the skeleton — a root first (glTF ignores a skinned
// mesh node's transform) — and the clip's morph-weight tracks of that mesh as
// a weights channel. Times and values are 32-bit floats, as glTF requires.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "armature/engine/anim/clip.h"
#include "armature/base/status.h"

namespace armature {

struct Mesh;  // engine/include/armature/engine/mesh/mesh.h

// The largest export the writer builds by default (the server passes its
// reply limit).
inline constexpr uint64_t kMaxGltfExportBytes = uint64_t{1} << 30;
// asset.extras key of a written file's skeleton units per centimetre, when
// they are not glTF's metres (a BVH skeleton in centimetres: 1); read back at import.
inline constexpr const char* kUnitsPerCentimetreExtra = "armatureUnitsPerCentimetre";

struct GltfExportOptions {
  bool binary = true;                        // .glb (one BIN chunk), else .gltf with the buffer as a data: URI
  std::string animation_name = "clip";       // the glTF animation's name
  uint64_t max_bytes = kMaxGltfExportBytes;  // RESOURCE_EXHAUSTED beyond, before allocating
};

// An upper bound of the size ExportGltf's output will have, in bytes, in
// O(joints + meshes + tracks); saturates at UINT64_MAX. A caller can refuse
// an export before any work.
uint64_t GltfExportByteEstimate(const Clip& clip, std::span<const Mesh* const> meshes, bool binary);

// Writes `clip` (and `meshes`, each skinned to clip.skeleton: its joints index
// that skeleton) as glTF. INVALID_ARGUMENT for a clip that does not match its
// skeleton, a mesh whose joints are outside it, or a value no 32-bit float can
// hold; RESOURCE_EXHAUSTED naming the size when GltfExportByteEstimate (plus
// the animation name's length) exceeds options.max_bytes.
StatusOr<std::string> ExportGltf(const Clip& clip, std::span<const Mesh* const> meshes = {},
                                 const GltfExportOptions& options = {});

}  // namespace armature
