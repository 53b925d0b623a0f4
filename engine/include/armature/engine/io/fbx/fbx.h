// FBX import (binary and ASCII, through assimp), from memory only.
//
// One file gives one Skeleton made of all its nodes (parents before children;
// rest = the node's transform with pre- and post-rotations and pivots folded
// in, so a Mixamo rig keeps its joint names and count; assimp's identity
// "RootNode" is left out), a Clip per animation stack ("<name>.<stack>"), and
// a Mesh per assimp mesh ("<name>.<mesh>": an FBX geometry splits by
// material) with its skin weights and morph targets. An unskinned mesh is bound
// rigidly to its node. Values stay in the file's units; the unit
// (UnitScaleFactor, centimetres per unit) and the up axis are reported as an
// import warning line.
//
// The file may name external textures or other files: none is read (every
// path assimp asks for is refused) and no image is decoded. assimp's failures
// are INVALID_ARGUMENT ("FBX: ..."), an incomplete scene too; sizes are
// checked against `limits` before our copies are made (RESOURCE_EXHAUSTED
// naming the limit). assimp first reads the bytes in a child process, so
// what it leaks on a failed read, a crash, or a read over 120 s (then
// killed) costs this process nothing: a good file is read twice.
#pragma once

#include <string_view>

#include "armature/base/status.h"
#include "armature/engine/io/asset.h"

namespace armature {

StatusOr<AssetContents> ParseFbx(std::string_view bytes, std::string_view name, const ImportLimits& limits = {});

// True when `bytes` start as an FBX file: "Kaydara FBX Binary" or an ASCII
// file's "; FBX" comment header.
bool LooksLikeFbx(std::string_view bytes);

}  // namespace armature
