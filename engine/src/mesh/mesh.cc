#include "armature/engine/mesh/mesh.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <utility>

namespace armature {

namespace {

constexpr uint32_t kMaxExactInfluences = 8;

// Influence count of a runtime group: exact up to 8, then padded to a
// multiple of 4 so the generic loop runs whole steps.
uint32_t PaddedCount(uint32_t k) { return k <= kMaxExactInfluences ? k : (k + 3) / 4 * 4; }

Status CheckVectors(const std::vector<Eigen::Vector3f>& v, const char* field) {
  for (size_t i = 0; i < v.size(); ++i)
    if (!v[i].allFinite())
      return Status::InvalidArgument(std::string(field) + "[" + std::to_string(i) + "] is not finite");
  return Status::Ok();
}

Status CheckMaterialGroups(const Mesh& mesh) {
  if (mesh.material_groups.empty()) return Status::Ok();
  uint64_t next = 0;
  for (size_t g = 0; g < mesh.material_groups.size(); ++g) {
    const MaterialGroup& group = mesh.material_groups[g];
    const std::string where = "material_groups[" + std::to_string(g) + "]";
    if (group.first_triangle != next)
      return Status::InvalidArgument(where + " starts at triangle " + std::to_string(group.first_triangle) +
                                     ", expected " + std::to_string(next));
    if (group.material < -1 || group.material >= static_cast<int>(mesh.materials.size()) ||
        (group.material >= 0 && !mesh.materials[static_cast<size_t>(group.material)]))
      return Status::InvalidArgument(where + ": material " + std::to_string(group.material) + " does not exist");
    next += group.triangle_count;
  }
  if (next != mesh.triangles.size() / 3)
    return Status::InvalidArgument("material_groups cover " + std::to_string(next) + " of " +
                                   std::to_string(mesh.triangles.size() / 3) + " triangles");
  return Status::Ok();
}

Status CheckMesh(const Mesh& mesh) {
  const size_t n = mesh.positions.size();
  if (n == 0) return Status::InvalidArgument("mesh '" + mesh.name + "' has no vertices");
  if (n >= UINT32_MAX) return Status::InvalidArgument("mesh '" + mesh.name + "' has too many vertices");
  ARMATURE_RETURN_IF_ERROR(CheckVectors(mesh.positions, "positions"));
  if (!mesh.normals.empty() && mesh.normals.size() != n)
    return Status::InvalidArgument("normals: " + std::to_string(mesh.normals.size()) + " for " + std::to_string(n) +
                                   " vertices");
  ARMATURE_RETURN_IF_ERROR(CheckVectors(mesh.normals, "normals"));
  if (!mesh.uvs.empty() && mesh.uvs.size() != n)
    return Status::InvalidArgument("uvs: " + std::to_string(mesh.uvs.size()) + " for " + std::to_string(n) +
                                   " vertices");
  for (size_t i = 0; i < mesh.uvs.size(); ++i)
    if (!mesh.uvs[i].allFinite()) return Status::InvalidArgument("uvs[" + std::to_string(i) + "] is not finite");
  if (mesh.triangles.size() % 3 != 0) return Status::InvalidArgument("triangles: index count is not a multiple of 3");
  ARMATURE_RETURN_IF_ERROR(CheckMaterialGroups(mesh));
  for (size_t i = 0; i < mesh.triangles.size(); ++i)
    if (mesh.triangles[i] >= n)
      return Status::InvalidArgument("triangles[" + std::to_string(i) + "] = " + std::to_string(mesh.triangles[i]) +
                                     " is out of range (" + std::to_string(n) + " vertices)");
  if (mesh.inverse_bind.size() != mesh.joints.size())
    return Status::InvalidArgument("inverse_bind: " + std::to_string(mesh.inverse_bind.size()) + " matrices for " +
                                   std::to_string(mesh.joints.size()) + " joints");
  if (mesh.joints.size() > UINT16_MAX)
    return Status::InvalidArgument("skin has " + std::to_string(mesh.joints.size()) + " joints (at most 65535)");
  for (size_t k = 0; k < mesh.joints.size(); ++k) {
    if (mesh.joints[k] < 0) return Status::InvalidArgument("joints[" + std::to_string(k) + "] is negative");
    if (!mesh.inverse_bind[k].matrix().allFinite())
      return Status::InvalidArgument("inverse_bind[" + std::to_string(k) + "] is not finite");
  }
  if (mesh.skinned()) {
    if (mesh.influence_offsets.size() != n + 1 || mesh.influence_offsets.front() != 0)
      return Status::InvalidArgument("influence_offsets: expected " + std::to_string(n + 1) + " offsets from 0");
    for (size_t v = 0; v < n; ++v)
      if (mesh.influence_offsets[v + 1] < mesh.influence_offsets[v])
        return Status::InvalidArgument("influence_offsets decrease at vertex " + std::to_string(v));
    const size_t total = mesh.influence_offsets.back();
    if (mesh.influence_joints.size() != total || mesh.influence_weights.size() != total)
      return Status::InvalidArgument("influence arrays disagree with influence_offsets");
    for (size_t i = 0; i < total; ++i) {
      if (mesh.influence_joints[i] >= mesh.joints.size())
        return Status::InvalidArgument("influence_joints[" + std::to_string(i) +
                                       "] = " + std::to_string(mesh.influence_joints[i]) + " is out of range (" +
                                       std::to_string(mesh.joints.size()) + " joints)");
      const float w = mesh.influence_weights[i];
      if (!std::isfinite(w) || w < 0)
        return Status::InvalidArgument("influence_weights[" + std::to_string(i) + "] is negative or not finite");
    }
  } else if (!mesh.influence_offsets.empty() || !mesh.influence_joints.empty()) {
    return Status::InvalidArgument("influences given for a mesh without joints");
  }
  if (mesh.default_weights.size() != mesh.targets.size())
    return Status::InvalidArgument("default_weights: " + std::to_string(mesh.default_weights.size()) + " for " +
                                   std::to_string(mesh.targets.size()) + " morph targets");
  for (size_t t = 0; t < mesh.targets.size(); ++t) {
    const MorphTarget& target = mesh.targets[t];
    const std::string who = "targets[" + std::to_string(t) + "]";
    if (!std::isfinite(mesh.default_weights[t]))
      return Status::InvalidArgument("default_weights[" + std::to_string(t) + "] is not finite");
    if (target.position_deltas.size() != target.vertices.size() ||
        (!target.normal_deltas.empty() && target.normal_deltas.size() != target.vertices.size()))
      return Status::InvalidArgument(who + ": delta count differs from vertex count");
    for (size_t i = 0; i < target.vertices.size(); ++i) {
      if (target.vertices[i] >= n || (i > 0 && target.vertices[i] <= target.vertices[i - 1]))
        return Status::InvalidArgument(who + ".vertices must be increasing and in range");
    }
    ARMATURE_RETURN_IF_ERROR(CheckVectors(target.position_deltas, (who + ".position_deltas").c_str()));
    ARMATURE_RETURN_IF_ERROR(CheckVectors(target.normal_deltas, (who + ".normal_deltas").c_str()));
  }
  return Status::Ok();
}

// Drops zero weights, sorts each vertex's influences by weight (largest
// first: it is the pivot of dual quaternion blending) and scales them to sum 1.
Status NormalizeInfluences(Mesh& mesh, std::vector<std::string>* warnings) {
  const size_t n = mesh.positions.size();
  std::vector<uint32_t> offsets(n + 1, 0);
  std::vector<uint32_t> joints;
  std::vector<float> weights;
  joints.reserve(mesh.influence_joints.size());
  weights.reserve(mesh.influence_weights.size());
  std::vector<std::pair<float, uint32_t>> vertex;
  size_t off_sum = 0;
  size_t worst_vertex = 0;
  double worst_sum = 1;
  for (size_t v = 0; v < n; ++v) {
    vertex.clear();
    double sum = 0;
    for (uint32_t i = mesh.influence_offsets[v]; i < mesh.influence_offsets[v + 1]; ++i) {
      const float w = mesh.influence_weights[i];
      if (w <= 0) continue;
      // The same joint listed twice (JOINTS_0 and JOINTS_1) adds up.
      auto same = std::find_if(vertex.begin(), vertex.end(),
                               [&](const auto& p) { return p.second == mesh.influence_joints[i]; });
      if (same != vertex.end())
        same->first += w;
      else
        vertex.emplace_back(w, mesh.influence_joints[i]);
      sum += w;
    }
    if (vertex.empty())
      return Status::InvalidArgument("vertex " + std::to_string(v) + " has no joint with a positive weight");
    if (std::abs(sum - 1) > 1e-3) {
      if (off_sum == 0 || std::abs(sum - 1) > std::abs(worst_sum - 1)) worst_vertex = v, worst_sum = sum;
      ++off_sum;
    }
    std::stable_sort(vertex.begin(), vertex.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (const auto& [w, j] : vertex) {
      joints.push_back(j);
      weights.push_back(static_cast<float>(w / sum));
    }
    offsets[v + 1] = static_cast<uint32_t>(joints.size());
  }
  if (off_sum > 0 && warnings)
    warnings->push_back(std::to_string(off_sum) + " vertices had weights not summing to 1 (e.g. vertex " +
                        std::to_string(worst_vertex) + ": " + std::to_string(worst_sum) + "); normalized");
  mesh.influence_offsets = std::move(offsets);
  mesh.influence_joints = std::move(joints);
  mesh.influence_weights = std::move(weights);
  return Status::Ok();
}

void BuildLayout(Mesh& mesh) {
  const size_t n = mesh.positions.size();
  SkinningLayout& l = mesh.layout;
  l = SkinningLayout{};
  auto count = [&](size_t v) -> uint32_t {
    return mesh.skinned() ? mesh.influence_offsets[v + 1] - mesh.influence_offsets[v] : 0;
  };
  l.order.resize(n);
  std::iota(l.order.begin(), l.order.end(), 0u);
  std::stable_sort(l.order.begin(), l.order.end(),
                   [&](uint32_t a, uint32_t b) { return PaddedCount(count(a)) < PaddedCount(count(b)); });
  std::vector<uint32_t> runtime_of(n);
  for (uint32_t r = 0; r < n; ++r) runtime_of[l.order[r]] = r;

  l.x.resize(n), l.y.resize(n), l.z.resize(n);
  const bool normals = !mesh.normals.empty();
  if (normals) l.nx.resize(n), l.ny.resize(n), l.nz.resize(n);
  for (uint32_t r = 0; r < n; ++r) {
    const uint32_t v = l.order[r];
    l.x[r] = mesh.positions[v].x(), l.y[r] = mesh.positions[v].y(), l.z[r] = mesh.positions[v].z();
    if (normals) {
      // Unit rest normals let rigid skinning skip renormalizing (zero stays zero).
      const Eigen::Vector3f n = mesh.normals[v].squaredNorm() > 0 ? mesh.normals[v].normalized() : mesh.normals[v];
      l.nx[r] = n.x(), l.ny[r] = n.y(), l.nz[r] = n.z();
    }
  }
  std::unordered_map<uint32_t, uint32_t> slot_of;  // (pivot << 16 | joint) → pair slot
  for (uint32_t r = 0; r < n;) {
    SkinningLayout::Group g;
    g.begin = r;
    g.influences = PaddedCount(count(l.order[r]));
    g.first = l.joints.size();
    for (; r < n && PaddedCount(count(l.order[r])) == g.influences; ++r) {
      const uint32_t v = l.order[r];
      const uint32_t k = count(v);
      const uint16_t pivot = k > 0 ? static_cast<uint16_t>(mesh.influence_joints[mesh.influence_offsets[v]]) : 0;
      for (uint32_t i = 0; i < g.influences; ++i) {
        const bool real = i < k;
        const uint32_t src = mesh.skinned() ? mesh.influence_offsets[v] + i : 0;
        const uint16_t joint = real ? static_cast<uint16_t>(mesh.influence_joints[src]) : pivot;
        l.joints.push_back(joint);
        l.weights.push_back(real ? mesh.influence_weights[src] : 0.f);
        const auto [it, added] =
            slot_of.try_emplace(uint32_t{pivot} << 16 | joint, static_cast<uint32_t>(l.pairs.size()));
        if (added) l.pairs.emplace_back(pivot, joint);
        l.pair_offsets.push_back(8 * it->second);
      }
    }
    g.end = r;
    l.groups.push_back(g);
  }
  for (const MorphTarget& t : mesh.targets) {
    SkinningLayout::Target rt;
    std::vector<std::pair<uint32_t, size_t>> entries;
    for (size_t i = 0; i < t.vertices.size(); ++i) entries.emplace_back(runtime_of[t.vertices[i]], i);
    std::sort(entries.begin(), entries.end());
    const bool target_normals = normals && !t.normal_deltas.empty();
    for (const auto& [r, i] : entries) {
      rt.vertices.push_back(r);
      rt.dx.push_back(t.position_deltas[i].x()), rt.dy.push_back(t.position_deltas[i].y());
      rt.dz.push_back(t.position_deltas[i].z());
      if (target_normals) {
        rt.nx.push_back(t.normal_deltas[i].x()), rt.ny.push_back(t.normal_deltas[i].y());
        rt.nz.push_back(t.normal_deltas[i].z());
      }
    }
    l.targets.push_back(std::move(rt));
  }
}

}  // namespace

size_t Mesh::max_influences() const {
  size_t m = 0;
  for (size_t v = 0; v + 1 < influence_offsets.size(); ++v)
    m = std::max<size_t>(m, influence_offsets[v + 1] - influence_offsets[v]);
  return m;
}

std::vector<size_t> Mesh::influence_histogram() const {
  std::vector<size_t> h(max_influences() + 1, 0);
  if (!skinned()) {
    h[0] = vertex_count();
    return h;
  }
  for (size_t v = 0; v + 1 < influence_offsets.size(); ++v) ++h[influence_offsets[v + 1] - influence_offsets[v]];
  return h;
}

Status FinalizeMesh(Mesh& mesh, std::vector<std::string>* warnings) {
  ARMATURE_RETURN_IF_ERROR(CheckMesh(mesh).WithContext("mesh '" + mesh.name + "': "));
  if (mesh.skinned())
    ARMATURE_RETURN_IF_ERROR(NormalizeInfluences(mesh, warnings).WithContext("mesh '" + mesh.name + "': "));
  BuildLayout(mesh);
  return Status::Ok();
}

std::vector<Eigen::Vector3f> ComputeVertexNormals(const std::vector<Eigen::Vector3f>& positions,
                                                  const std::vector<uint32_t>& triangles) {
  std::vector<Eigen::Vector3f> normals(positions.size(), Eigen::Vector3f::Zero());
  for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const uint32_t a = triangles[t], b = triangles[t + 1], c = triangles[t + 2];
    if (a >= positions.size() || b >= positions.size() || c >= positions.size()) continue;
    // The cross product's length is twice the area: area weighting for free.
    const Eigen::Vector3f n = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
    normals[a] += n, normals[b] += n, normals[c] += n;
  }
  for (Eigen::Vector3f& n : normals) {
    const float len = n.norm();
    if (len > 0) n /= len;
  }
  return normals;
}

}  // namespace armature
