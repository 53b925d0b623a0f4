// Helpers shared by the mesh, skinning and glTF tests (and the skinning
// benchmark): loading glTF files and building procedural meshes.
#pragma once

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "armature/engine/io/asset.h"
#include "armature/engine/io/gltf/gltf.h"
#include "armature/engine/mesh/mesh.h"
#include "armature/engine/anim/skeleton.h"
#include "test_files.h"

namespace armature::test_util {

// Reads a .gltf and the external files its buffers name (as a server would
// receive them), then imports it.
inline StatusOr<AssetContents> LoadGltfFile(const std::filesystem::path& path, const std::string& name) {
  auto bytes = ReadFileBytes(path);
  if (!bytes) return Status::NotFound("cannot read " + path.string());
  ResourceMap resources;
  const bool binary = path.extension() == ".glb";
  if (!binary) {
    const auto json = nlohmann::json::parse(*bytes);
    for (const auto& buffer : json.value("buffers", nlohmann::json::array())) {
      const std::string uri = buffer.value("uri", "");
      if (uri.empty() || uri.rfind("data:", 0) == 0) continue;
      auto extra = ReadFileBytes(path.parent_path() / uri);
      if (!extra) return Status::NotFound("cannot read " + uri);
      resources[uri] = *extra;
    }
  }
  return ParseGltf(*bytes, binary, name, resources);
}

// A chain of `bones` joints along +Z, each `length` long, as a skeleton.
inline std::shared_ptr<Skeleton> MakeChain(int bones, double length) {
  auto s = std::make_shared<Skeleton>();
  for (int i = 0; i < bones; ++i) {
    s->names.push_back("bone" + std::to_string(i));
    s->parents.push_back(i - 1);
    Trs rest;
    if (i > 0) rest.translation = {0, 0, length};
    s->rest.push_back(rest);
  }
  s->channels.resize(static_cast<size_t>(bones));
  s->end_sites.assign(static_cast<size_t>(bones), std::nullopt);
  s->end_sites.back() = Eigen::Vector3d(0, 0, length);
  return s;
}

// A closed-side cylinder of `radius` around +Z from z = 0 to `height`, with
// `rings` × `segments` vertices and outward normals (no caps).
inline Mesh MakeCylinder(double radius, double height, int rings, int segments) {
  Mesh m;
  m.name = "cylinder";
  for (int r = 0; r < rings; ++r) {
    const double z = height * r / (rings - 1);
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * std::numbers::pi * s / segments;
      m.positions.emplace_back(static_cast<float>(radius * std::cos(a)), static_cast<float>(radius * std::sin(a)),
                               static_cast<float>(z));
      m.normals.emplace_back(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)), 0.f);
    }
  }
  for (int r = 0; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const auto i = static_cast<uint32_t>(r * segments + s);
      const auto j = static_cast<uint32_t>(r * segments + (s + 1) % segments);
      const auto k = static_cast<uint32_t>(i + segments), l = static_cast<uint32_t>(j + segments);
      m.triangles.insert(m.triangles.end(), {i, j, l, i, l, k});
    }
  return m;
}

// Skins `mesh` (along +Z) to a chain of `bones` joints of `length`: each
// vertex takes up to `influences` nearest joints with weights falling off
// linearly with distance along Z, and inverse bind matrices of the chain's rest.
inline void BindAlongZ(Mesh& mesh, const Skeleton& chain, double length, int influences) {
  const int bones = static_cast<int>(chain.size());
  mesh.joints.clear();
  mesh.inverse_bind.clear();
  for (int b = 0; b < bones; ++b) {
    mesh.joints.push_back(b);
    Eigen::Affine3d bind = Eigen::Affine3d::Identity();
    bind.translation() = Eigen::Vector3d(0, 0, b * length);
    mesh.inverse_bind.push_back(bind.inverse());
  }
  mesh.influence_offsets = {0};
  mesh.influence_joints.clear();
  mesh.influence_weights.clear();
  for (const Eigen::Vector3f& p : mesh.positions) {
    const double u = p.z() / length - 0.5;  // bone centres at u = 0, 1, …
    std::vector<std::pair<double, int>> near;
    for (int b = 0; b < bones; ++b) near.emplace_back(std::abs(u - b), b);
    std::sort(near.begin(), near.end());
    double sum = 0;
    std::vector<std::pair<double, int>> kept;
    for (int k = 0; k < influences && k < bones; ++k) {
      const double w = std::max(1e-3, 1.0 + influences * 0.5 - near[static_cast<size_t>(k)].first);
      kept.emplace_back(w, near[static_cast<size_t>(k)].second);
      sum += w;
    }
    for (const auto& [w, b] : kept) {
      mesh.influence_joints.push_back(static_cast<uint32_t>(b));
      mesh.influence_weights.push_back(static_cast<float>(w / sum));
    }
    mesh.influence_offsets.push_back(static_cast<uint32_t>(mesh.influence_joints.size()));
  }
}

}  // namespace armature::test_util
