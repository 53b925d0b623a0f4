// glTF 2.0 import (via tinygltf), from memory only.
//
// One file gives one Skeleton made of all its nodes (parents before
// children; rest = the node's TRS, matrices decomposed), shared by every skin;
// a Clip per animation (translation, rotation, scale and weights channels;
// STEP, LINEAR and CUBICSPLINE kept as the file has them); a Mesh per glTF
// mesh (primitives concatenated; POSITION, NORMAL, indices, JOINTS_n/WEIGHTS_n
// for any n, morph targets with POSITION and NORMAL deltas, default weights
// and names from extras.targetNames). A skinned mesh references the skin's
// joints and inverse bind matrices; a mesh on a node without a skin is bound
// rigidly to that node, so it follows the node's animation.
#pragma once

#include <string_view>

#include "armature/engine/io/asset.h"
#include "armature/base/status.h"

namespace armature {

// `binary`: a .glb container, else .gltf JSON. External buffers come from
// `resources` keyed by their uri. Errors are INVALID_ARGUMENT naming the
// field and accessor, e.g. "meshes[0].primitives[0].attributes.JOINTS_0:
// accessor 7 has type VEC3, expected VEC4".
// The GLB header and chunk lengths are checked before tinygltf reads them;
// accessor bounds use overflow-checked arithmetic; sizes are checked against
// `limits` before decoding (RESOURCE_EXHAUSTED naming the limit). Node, mesh,
// animation and morph target names must be UTF-8.
StatusOr<AssetContents> ParseGltf(std::string_view bytes, bool binary, std::string_view name,
                                  const ResourceMap& resources = {}, const ImportLimits& limits = {});

}  // namespace armature
