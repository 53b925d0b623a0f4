// What one imported file yields: named skeletons, clips and meshes. Parsed
// once at import (import-time data); the server hands the parts out as
// shared_ptr<const …> so a delete never breaks an in-flight call.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "armature/engine/anim/clip.h"
#include "armature/engine/io/import_limits.h"
#include "armature/engine/anim/skeleton.h"
#include "armature/base/status.h"

namespace armature {

struct Mesh;            // engine/include/armature/engine/mesh/mesh.h
struct CompressedClip;  // engine/include/armature/engine/anim/compression/compressed_clip.h

enum class AssetFormat { kBvh, kGltf, kGlb, kObj, kFbx };

std::string_view FormatName(AssetFormat f);       // "bvh", "gltf", "glb", "obj", "fbx"
std::string_view FormatExtension(AssetFormat f);  // ".bvh" …

struct NamedSkeleton {
  std::string name;
  std::shared_ptr<const Skeleton> skeleton;
};
struct NamedClip {
  std::string name;
  std::string skeleton_name;  // the NamedSkeleton it animates
  // The parsed keys. The server drops them once `runtime` is set unless it is
  // exact (then they are its keys): read the runtime form instead.
  std::shared_ptr<const Clip> clip;
  // `clip`'s runtime form (CompressClip, under the import's precision), set by
  // whoever loads the asset for sampling (the server, at import and load); all
  // sampling goes through it (ClipSamplingJob).
  std::shared_ptr<const CompressedClip> runtime = nullptr;
};
struct NamedMesh {
  std::string name;
  std::string skeleton_name;  // the NamedSkeleton it is skinned to; empty when the mesh has no skin
  std::shared_ptr<const Mesh> mesh;
};

struct AssetContents {
  std::vector<NamedSkeleton> skeletons;
  std::vector<NamedClip> clips;
  std::vector<NamedMesh> meshes;
  // Problems the importer repaired (e.g. skin weights not summing to 1, normalized).
  std::vector<std::string> warnings;
};

// Format from an explicit name ("bvh", "gltf", "glb", "obj", "fbx"), else the
// filename's extension, else the content's first bytes (FBX: "Kaydara FBX
// Binary" or an ASCII "; FBX" header).
StatusOr<AssetFormat> DetectFormat(std::string_view explicit_format, std::string_view filename, std::string_view bytes);

// Further files a main file refers to (a .gltf's external .bin buffers),
// keyed by the uri the main file uses.
using ResourceMap = std::map<std::string, std::string, std::less<>>;

// Parses `bytes` into named parts. Parts are named after `name` (a BVH file
// "walk" gives skeleton "walk" and clip "walk").
// glTF: one skeleton `name` made of all nodes, a clip per animation
// ("<name>.<animation name or index>") and a mesh per glTF mesh
// ("<name>.<mesh name or index>"); see gltf.h. OBJ: one unbound mesh `name`.
// FBX: as glTF, a clip per animation stack ("<name>.<stack>"); see fbx.h.
// A resource the asset needs but `resources` lacks is INVALID_ARGUMENT naming its uri.
// Total: any bytes give contents or a Status promptly, never an exception;
// sizes are checked against `limits` and the input before allocating.
StatusOr<AssetContents> ParseAsset(AssetFormat format, std::string_view bytes, std::string_view name,
                                   const ResourceMap& resources = {}, const ImportLimits& limits = {});

}  // namespace armature
