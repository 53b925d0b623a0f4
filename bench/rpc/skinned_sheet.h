// The 100k-vertex sheet (sheet_mesh.h) as a skinned binary glTF written
// here: two joints ("root" at the origin, "bend" one unit along x), each
// vertex weighted by its x across the sheet, and an animation "bend" turning
// the second joint 90° about z over one second. Imported once into the shared
// bench server; SkinMesh on it answers 100,489 positions and normals.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "rpc_bench_server.h"
#include "sheet_mesh.h"

namespace armature_bench {

inline constexpr char kSkinnedSheetAsset[] = "skinsheet";
inline constexpr char kSkinnedSheetMesh[] = "skinsheet.sheet";
inline constexpr char kSkinnedSheetClip[] = "skinsheet.bend";

inline std::string SkinnedSheetGlb() {
  const auto& m = Sheet();
  const auto n = static_cast<size_t>(m.positions.rows());
  std::string bin;
  struct View {
    size_t offset, length;
  };
  std::vector<View> views;
  auto add = [&](const void* data, size_t bytes) {
    while (bin.size() % 4) bin.push_back('\0');
    views.push_back({bin.size(), bytes});
    bin.append(static_cast<const char*>(data), bytes);
  };
  std::vector<float> positions(3 * n);
  double lo[3] = {1e30, 1e30, 1e30}, hi[3] = {-1e30, -1e30, -1e30};
  for (size_t v = 0; v < n; ++v)
    for (int k = 0; k < 3; ++k) {
      positions[3 * v + k] = static_cast<float>(m.positions(static_cast<Eigen::Index>(v), k));
      lo[k] = std::min(lo[k], static_cast<double>(positions[3 * v + k]));
      hi[k] = std::max(hi[k], static_cast<double>(positions[3 * v + k]));
    }
  std::vector<uint8_t> joints(4 * n, 0);
  std::vector<float> weights(4 * n, 0.f);
  for (size_t v = 0; v < n; ++v) {
    const float w = static_cast<float>((positions[3 * v] - lo[0]) / (hi[0] - lo[0]));
    joints[4 * v + 1] = 1;
    weights[4 * v] = 1 - w;
    weights[4 * v + 1] = w;
  }
  const std::vector<uint32_t>& indices = m.triangles;
  // Column-major inverse bind matrices: identity, and a translation by -1 in x.
  float ibm[32] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0, 0, 1};
  const float times[2] = {0, 1};
  const float s = static_cast<float>(std::sqrt(0.5));
  const float rotations[8] = {0, 0, 0, 1, 0, 0, s, s};  // x, y, z, w
  add(positions.data(), positions.size() * 4);
  add(joints.data(), joints.size());
  add(weights.data(), weights.size() * 4);
  add(indices.data(), indices.size() * 4);
  add(ibm, sizeof ibm);
  add(times, sizeof times);
  add(rotations, sizeof rotations);
  while (bin.size() % 4) bin.push_back('\0');

  auto view_json = [&](size_t i) {
    return "{\"buffer\":0,\"byteOffset\":" + std::to_string(views[i].offset) +
           ",\"byteLength\":" + std::to_string(views[i].length) + "}";
  };
  std::string bounds_min, bounds_max;
  for (int k = 0; k < 3; ++k) {
    bounds_min += (k ? "," : "") + std::to_string(lo[k]);
    bounds_max += (k ? "," : "") + std::to_string(hi[k]);
  }
  const std::string N = std::to_string(n);
  std::string json =
      R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],)"
      R"("nodes":[{"name":"root","children":[1],"mesh":0,"skin":0},{"name":"bend","translation":[1,0,0]}],)"
      R"("skins":[{"joints":[0,1],"skeleton":0,"inverseBindMatrices":4}],)"
      R"("meshes":[{"name":"sheet","primitives":[{"attributes":{"POSITION":0,"JOINTS_0":1,"WEIGHTS_0":2},"indices":3}]}],)"
      R"("animations":[{"name":"bend","channels":[{"sampler":0,"target":{"node":1,"path":"rotation"}}],)"
      R"("samplers":[{"input":5,"output":6,"interpolation":"LINEAR"}]}],)"
      R"("accessors":[)"
      R"({"bufferView":0,"componentType":5126,"type":"VEC3","count":)" +
      N + R"(,"min":[)" + bounds_min + R"(],"max":[)" + bounds_max +
      R"(]},)"
      R"({"bufferView":1,"componentType":5121,"type":"VEC4","count":)" +
      N +
      R"(},)"
      R"({"bufferView":2,"componentType":5126,"type":"VEC4","count":)" +
      N +
      R"(},)"
      R"({"bufferView":3,"componentType":5125,"type":"SCALAR","count":)" +
      std::to_string(indices.size()) +
      R"(},)"
      R"({"bufferView":4,"componentType":5126,"type":"MAT4","count":2},)"
      R"({"bufferView":5,"componentType":5126,"type":"SCALAR","count":2,"min":[0],"max":[1]},)"
      R"({"bufferView":6,"componentType":5126,"type":"VEC4","count":2}],)"
      R"("bufferViews":[)";
  for (size_t i = 0; i < views.size(); ++i) json += (i ? "," : "") + view_json(i);
  json += R"(],"buffers":[{"byteLength":)" + std::to_string(bin.size()) + "}]}";
  while (json.size() % 4) json += ' ';

  std::string glb;
  auto u32 = [&glb](uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };  // little-endian hosts
  glb = "glTF";
  u32(2);
  u32(static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  u32(static_cast<uint32_t>(json.size()));
  glb += "JSON";
  glb += json;
  u32(static_cast<uint32_t>(bin.size()));
  glb.append("BIN\0", 4);
  glb += bin;
  return glb;
}

inline const std::string& ImportedSkinnedSheet() {
  static const std::string mesh = [] {
    Server().client->Import({"skinsheet.glb", SkinnedSheetGlb()}, kSkinnedSheetAsset);
    return std::string(kSkinnedSheetMesh);
  }();
  return mesh;
}

}  // namespace armature_bench
