// Shared by the writer fuzz targets: a clip written as BVH must read back
// with the same joints and frame count; a clip written as glTF (with the
// file's skinned meshes) must read back with its joints and meshes.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <vector>

#include "armature/engine/io/asset.h"
#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/gltf/gltf.h"
#include "armature/engine/io/gltf/gltf_writer.h"
#include "armature/engine/mesh/mesh.h"
#include "fuzz_limits.h"

namespace armature::fuzz {

inline void ExpectBvhRoundTrip(const Clip& clip) {
  if (BvhExportFrameCount(clip) > kMaxExportFrames) {
    if (ExportBvh(clip, kMaxExportFrames).ok()) std::abort();  // the cap must hold
    return;
  }
  auto text = ExportBvh(clip, kMaxExportFrames);
  if (!text.ok()) {
    std::fprintf(stderr, "export failed: %s\n", text.status().message().c_str());
    std::abort();
  }
  ImportLimits limits = Limits();
  limits.max_clip_frames = kMaxExportFrames;
  auto back = ParseBvh(*text, limits);
  if (!back.ok()) {
    std::fprintf(stderr, "re-parse failed: %s\n", back.status().message().c_str());
    std::abort();
  }
  // Names are compared by count only: the writer replaces what BVH cannot
  // hold (control characters, blanks at the ends, a trailing '{').
  if (back->skeleton->size() != clip.skeleton->size() || back->clip->frame_count != BvhExportFrameCount(clip))
    std::abort();
}

// Bytes the glTF writer round-trips fuzz clips up to (its copies stay far
// below libFuzzer's malloc limit).
inline constexpr uint64_t kMaxGltfExportBytes = 16 << 20;

inline void ExpectGltfRoundTrip(const Clip& clip, const AssetContents& contents, bool binary) {
  std::vector<const Mesh*> meshes;
  for (const NamedMesh& m : contents.meshes)
    if (m.mesh->skinned()) meshes.push_back(m.mesh.get());
  GltfExportOptions options;
  options.binary = binary;
  options.max_bytes = kMaxGltfExportBytes;
  auto bytes = ExportGltf(clip, meshes, options);
  if (GltfExportByteEstimate(clip, meshes, binary) > kMaxGltfExportBytes) {
    if (bytes.ok()) std::abort();  // the cap must hold
    return;
  }
  if (!bytes.ok()) {
    std::fprintf(stderr, "glTF export failed: %s\n", bytes.status().message().c_str());
    std::abort();
  }
  if (bytes->size() > GltfExportByteEstimate(clip, meshes, binary)) std::abort();  // the estimate bounds the size
  auto back = ParseGltf(*bytes, binary, "back", {}, Limits());
  if (!back.ok()) {
    std::fprintf(stderr, "glTF re-parse failed: %s\n", back.status().message().c_str());
    std::abort();
  }
  // Every joint comes back (plus a node per mesh that found no free joint).
  if (back->skeletons.empty() || back->skeletons[0].skeleton->size() < clip.skeleton->size() ||
      back->meshes.size() != meshes.size() || back->clips.size() > 1)
    std::abort();
}

}  // namespace armature::fuzz
