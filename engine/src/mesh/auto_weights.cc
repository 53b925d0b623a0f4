#include "armature/engine/mesh/auto_weights.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include "armature/engine/kinematics/fk.h"
#include "armature/engine/mesh/mesh_topology.h"

namespace armature {

namespace {

struct Segment {
  Eigen::Vector3d a, b;
};

// Closest point to p on segment ab.
Eigen::Vector3d Closest(const Segment& s, const Eigen::Vector3d& p) {
  const Eigen::Vector3d ab = s.b - s.a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - s.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return s.a + t * ab;
}

// Each joint's bones in rest world space.
std::vector<std::vector<Segment>> Bones(const Skeleton& skeleton, const std::vector<Eigen::Affine3d>& world) {
  const size_t n = skeleton.size();
  std::vector<std::vector<Segment>> bones(n);
  for (size_t c = 0; c < n; ++c) {
    const int p = skeleton.parents[c];
    if (p >= 0)
      bones[static_cast<size_t>(p)].push_back({world[static_cast<size_t>(p)].translation(), world[c].translation()});
  }
  for (size_t j = 0; j < n; ++j) {
    if (j < skeleton.end_sites.size() && skeleton.end_sites[j])
      bones[j].push_back({world[j].translation(), world[j] * *skeleton.end_sites[j]});
    if (bones[j].empty()) bones[j].push_back({world[j].translation(), world[j].translation()});
  }
  return bones;
}

struct Nearest {
  double distance;
  Eigen::Vector3d point;  // closest point on the joint's bones
};

Nearest NearestOnJoint(const std::vector<Segment>& segments, const Eigen::Vector3d& p) {
  Nearest best{std::numeric_limits<double>::infinity(), p};
  for (const Segment& s : segments) {
    const Eigen::Vector3d q = Closest(s, p);
    const double d = (q - p).norm();
    if (d < best.distance) best = {d, q};
  }
  return best;
}

// Keeps the `k` largest weights above `min_weight` (relative to the vertex's
// largest), renormalized, as CSR influences.
void KeepLargest(const std::vector<double>& weights, int k, double min_weight, Mesh& mesh) {
  std::vector<uint32_t> order(weights.size());
  std::iota(order.begin(), order.end(), 0u);
  const size_t keep = std::min<size_t>(static_cast<size_t>(std::max(k, 1)), order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<ptrdiff_t>(keep), order.end(),
                    [&](uint32_t a, uint32_t b) { return weights[a] > weights[b]; });
  const double top = weights[order[0]];
  double sum = 0;
  size_t used = 0;
  for (size_t i = 0; i < keep; ++i) {
    const double w = weights[order[i]];
    if (i > 0 && (w <= 0 || w < min_weight * top)) break;
    sum += w;
    ++used;
  }
  for (size_t i = 0; i < used; ++i) {
    mesh.influence_joints.push_back(order[i]);
    mesh.influence_weights.push_back(static_cast<float>(sum > 0 ? weights[order[i]] / sum : 1.0 / used));
  }
  mesh.influence_offsets.push_back(static_cast<uint32_t>(mesh.influence_joints.size()));
}

// The triangles with well-defined angles: degenerate ones (a repeated
// vertex, near-zero area) carry no cotangent weight and are skipped.
std::vector<uint32_t> ProperTriangles(const Mesh& mesh) {
  std::vector<uint32_t> kept;
  for (size_t t = 0; t + 2 < mesh.triangles.size(); t += 3) {
    const uint32_t v[3] = {mesh.triangles[t], mesh.triangles[t + 1], mesh.triangles[t + 2]};
    const Eigen::Vector3d p[3] = {mesh.positions[v[0]].cast<double>(), mesh.positions[v[1]].cast<double>(),
                                  mesh.positions[v[2]].cast<double>()};
    const double twice_area = (p[1] - p[0]).cross(p[2] - p[0]).norm();
    const double longest2 =
        std::max({(p[1] - p[0]).squaredNorm(), (p[2] - p[1]).squaredNorm(), (p[0] - p[2]).squaredNorm()});
    if (twice_area > 1e-10 * longest2) kept.insert(kept.end(), v, v + 3);
  }
  return kept;
}

// Cotangent stiffness matrix L (symmetric positive semi-definite, L·1 = 0)
// and barycentric vertex areas, from proper triangles.
void CotangentLaplacian(const Mesh& mesh, const std::vector<uint32_t>& triangles,
                        Eigen::SparseMatrix<double>* laplacian, std::vector<double>* area) {
  const size_t n = mesh.vertex_count();
  std::vector<Eigen::Triplet<double>> entries;
  area->assign(n, 0.0);
  for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const uint32_t v[3] = {triangles[t], triangles[t + 1], triangles[t + 2]};
    const Eigen::Vector3d p[3] = {mesh.positions[v[0]].cast<double>(), mesh.positions[v[1]].cast<double>(),
                                  mesh.positions[v[2]].cast<double>()};
    const double twice_area = (p[1] - p[0]).cross(p[2] - p[0]).norm();
    for (int i = 0; i < 3; ++i) {
      (*area)[v[i]] += twice_area / 6;
      // The angle at corner i is opposite edge (j, k): cot = a·b / |a×b|.
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      const double w = 0.5 * (p[j] - p[i]).dot(p[k] - p[i]) / twice_area;
      entries.emplace_back(v[j], v[k], -w);
      entries.emplace_back(v[k], v[j], -w);
      entries.emplace_back(v[j], v[j], w);
      entries.emplace_back(v[k], v[k], w);
    }
  }
  laplacian->resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  laplacian->setFromTriplets(entries.begin(), entries.end());
}

Status HeatWeights(const Mesh& mesh, const std::vector<std::vector<Segment>>& bones, const BindOptions& options,
                   std::vector<std::vector<double>>* weights, std::vector<std::string>* warnings) {
  const size_t n = mesh.vertex_count(), joints = bones.size();
  if (mesh.triangles.empty()) return Status::InvalidArgument("heat weights need a mesh with triangles");
  const std::vector<Eigen::Vector3f> normals =
      mesh.normals.empty() ? ComputeVertexNormals(mesh.positions, mesh.triangles) : mesh.normals;

  // Nearest visible bone of each vertex: H_ii = c/d², p_j(i) = 1.
  std::vector<double> h(n, 0.0);
  std::vector<int> nearest(n, -1);
  std::vector<int> nearest_any(n, -1);
  std::vector<double> nearest_any_distance(n, std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p = mesh.positions[i].cast<double>();
    const Eigen::Vector3d normal = normals[i].cast<double>();
    double best = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < joints; ++j) {
      const Nearest q = NearestOnJoint(bones[j], p);
      if (q.distance < nearest_any_distance[i])
        nearest_any_distance[i] = q.distance, nearest_any[i] = static_cast<int>(j);
      const bool visible = (q.point - p).dot(normal) < 1e-9 * q.distance;
      if (visible && q.distance < best) best = q.distance, nearest[i] = static_cast<int>(j);
    }
    if (nearest[i] >= 0) h[i] = options.heat / std::max(best * best, 1e-12);
  }
  // A component that sees no bone (e.g. inward normals) takes its nearest
  // bones regardless, or the system would be singular there.
  const std::vector<uint32_t> triangles = ProperTriangles(mesh);
  ARMATURE_ASSIGN_OR_RETURN(auto topology, BuildMeshTopology(n, triangles));
  const std::vector<uint32_t>& component = topology.component;
  std::vector<char> sees(topology.component_count, 0);
  for (size_t i = 0; i < n; ++i)
    if (h[i] > 0) sees[component[i]] = 1;
  size_t forced = 0;
  for (size_t i = 0; i < n; ++i)
    if (!sees[component[i]]) {
      nearest[i] = nearest_any[i];
      h[i] = options.heat / std::max(nearest_any_distance[i] * nearest_any_distance[i], 1e-12);
      ++forced;
    }
  if (forced > 0)
    warnings->push_back(std::to_string(forced) +
                        " vertices see no bone from their side of the surface (inward normals or a part "
                        "outside the skeleton?); their nearest bones were used");

  // (L + A·H)·w_j = A·H·p_j, with the cotangent stiffness L and areas A
  // (the area-weighted, symmetric form of (−Δ + H)·w = H·p).
  Eigen::SparseMatrix<double> system;
  std::vector<double> area;
  CotangentLaplacian(mesh, triangles, &system, &area);
  // Vertices on no triangle have no area; give them a unit mass so H binds them.
  for (double& a : area)
    if (!(a > 0)) a = 1;
  for (size_t i = 0; i < n; ++i)
    system.coeffRef(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) += area[i] * h[i];
  system.makeCompressed();
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(system);
  if (solver.info() != Eigen::Success)
    return Status::InvalidArgument("bone heat: the surface system could not be factored (degenerate mesh?)");

  weights->assign(n, std::vector<double>(joints, 0.0));
  Eigen::VectorXd rhs(static_cast<Eigen::Index>(n));
  for (size_t j = 0; j < joints; ++j) {
    bool any = false;
    for (size_t i = 0; i < n; ++i) {
      const bool mine = nearest[i] == static_cast<int>(j);
      rhs[static_cast<Eigen::Index>(i)] = mine ? area[i] * h[i] : 0.0;
      any |= mine;
    }
    if (!any) continue;  // no vertex has this bone nearest: w_j = 0
    const Eigen::VectorXd w = solver.solve(rhs);
    if (solver.info() != Eigen::Success) return Status::InvalidArgument("bone heat: solve failed");
    for (size_t i = 0; i < n; ++i) (*weights)[i][j] = w[static_cast<Eigen::Index>(i)];
  }
  return Status::Ok();
}

}  // namespace

StatusOr<BindResult> BindMesh(const Mesh& rest, const Skeleton& skeleton, const BindOptions& options) {
  ARMATURE_RETURN_IF_ERROR(skeleton.Validate());
  if (options.max_influences < 1) return Status::InvalidArgument("max_influences must be at least 1");
  if (!(options.falloff > 0) || !(options.heat > 0) || !(options.min_weight >= 0))
    return Status::InvalidArgument("falloff and heat must be positive, min_weight non-negative");
  if (rest.vertex_count() == 0) return Status::InvalidArgument("mesh '" + rest.name + "' has no vertices");
  if (skeleton.size() > UINT16_MAX) return Status::InvalidArgument("skeleton has too many joints to skin");

  std::vector<Eigen::Affine3d> world(skeleton.size());
  ComputeWorld(skeleton, skeleton.rest, world);
  const auto bones = Bones(skeleton, world);

  BindResult result;
  result.mesh = rest;
  Mesh& mesh = result.mesh;
  mesh.joints.resize(skeleton.size());
  std::iota(mesh.joints.begin(), mesh.joints.end(), 0);
  mesh.inverse_bind.clear();
  for (const Eigen::Affine3d& w : world) mesh.inverse_bind.push_back(w.inverse());
  mesh.skeleton_root = 0;
  mesh.influence_offsets = {0};
  mesh.influence_joints.clear();
  mesh.influence_weights.clear();

  std::vector<std::vector<double>> weights;
  if (options.method == WeightMethod::kHeat) {
    ARMATURE_RETURN_IF_ERROR(HeatWeights(rest, bones, options, &weights, &result.warnings));
  } else {
    weights.assign(rest.vertex_count(), std::vector<double>(skeleton.size()));
    for (size_t i = 0; i < rest.vertex_count(); ++i) {
      const Eigen::Vector3d p = rest.positions[i].cast<double>();
      for (size_t j = 0; j < skeleton.size(); ++j) {
        const double d = std::max(NearestOnJoint(bones[j], p).distance, 1e-9);
        weights[i][j] = std::pow(d, -options.falloff);
      }
    }
  }
  for (size_t i = 0; i < weights.size(); ++i) {
    auto& w = weights[i];
    if (!(*std::max_element(w.begin(), w.end()) > 0)) {
      // Nothing reached this vertex (possible with obtuse cotangent weights): nearest bone.
      const Eigen::Vector3d p = rest.positions[i].cast<double>();
      size_t best = 0;
      for (size_t j = 1; j < bones.size(); ++j)
        if (NearestOnJoint(bones[j], p).distance < NearestOnJoint(bones[best], p).distance) best = j;
      std::fill(w.begin(), w.end(), 0.0);
      w[best] = 1;
    }
    KeepLargest(w, options.max_influences, options.min_weight, mesh);
  }
  ARMATURE_RETURN_IF_ERROR(FinalizeMesh(mesh, nullptr));
  return result;
}

}  // namespace armature
