#include "vertex_pipeline.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "armature/engine/math/rotation.h"
#include "skinning_kernels.h"
#include "parallel/worker_pool.h"

namespace armature::skinning_internal {

namespace {

// Below this many vertices one core is faster than handing work to another.
constexpr size_t kParallelVertices = 16384;

void StoreColumns(const Eigen::Matrix3d& l, const Eigen::Vector3d& t, SkinningWorkspace::Matrix& out) {
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) out.c[4 * c + r] = static_cast<float>(l(r, c));
    out.c[4 * c + 3] = 0;
  }
  for (int r = 0; r < 3; ++r) out.c[12 + r] = static_cast<float>(t[r]);
  out.c[15] = 1;
}

// A uniform scale times a rotation or reflection: LᵀL = s²·I.
bool IsSimilarity(const Eigen::Matrix3d& l) {
  const Eigen::Matrix3d g = l.transpose() * l;
  const double s2 = g.trace() / 3;
  return s2 > 0 && (g - s2 * Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-5 * s2;
}

// Normals transform by L⁻ᵀ; scaled by |det L|^(2/3) it equals L for a
// similarity, so meshes without non-uniform scale get exactly the LBS matrix.
Eigen::Matrix3d NormalMatrix(const Eigen::Matrix3d& l) {
  const double det = l.determinant();
  if (std::abs(det) < 1e-300) {  // singular: the cofactor matrix still orients normals
    Eigen::Matrix3d cof;
    cof.col(0) = l.col(1).cross(l.col(2));
    cof.col(1) = l.col(2).cross(l.col(0));
    cof.col(2) = l.col(0).cross(l.col(1));
    return cof;
  }
  return l.inverse().transpose() * std::cbrt(det * det);
}

Status CheckFinite(const Eigen::Affine3d& m, size_t k) {
  if (!m.matrix().allFinite())
    return Status::InvalidArgument("skin joint " + std::to_string(k) + ": pose transform is not finite");
  return Status::Ok();
}

// Skin joint k's map from bind space to posed world space.
Eigen::Affine3d SkinMatrix(const Mesh& mesh, std::span<const Eigen::Affine3d> world, size_t k) {
  return world[static_cast<size_t>(mesh.joints[k])] * mesh.inverse_bind[k];
}

// LBS joint data; returns whether normals need their own matrices.
Status PrepareLinear(const Mesh& mesh, std::span<const Eigen::Affine3d> world, bool normals, SkinningWorkspace& ws,
                     bool* normal_matrices) {
  const size_t n = mesh.joints.size();
  Grow(ws.matrices, n);
  bool similar = true;
  for (size_t k = 0; k < n; ++k) {
    const Eigen::Affine3d m = SkinMatrix(mesh, world, k);
    ARMATURE_RETURN_IF_ERROR(CheckFinite(m, k));
    StoreColumns(m.linear(), m.translation(), ws.matrices[k]);
    if (normals && similar) similar = IsSimilarity(m.linear());
  }
  *normal_matrices = normals && !similar;
  if (*normal_matrices) {
    Grow(ws.normal_matrices, n);
    for (size_t k = 0; k < n; ++k) {
      const Eigen::Affine3d m = SkinMatrix(mesh, world, k);
      StoreColumns(NormalMatrix(m.linear()), Eigen::Vector3d::Zero(), ws.normal_matrices[k]);
    }
  }
  return Status::Ok();
}

// DQS joint data: each joint's map split as (rotation, translation) ∘ stretch
// by polar decomposition; returns whether any joint stretches.
Status PrepareDualQuaternion(const Mesh& mesh, std::span<const Eigen::Affine3d> world, SkinningWorkspace& ws,
                             bool* stretched) {
  const size_t n = mesh.joints.size();
  Grow(ws.dual_quaternions, n);
  Grow(ws.stretch, n);
  *stretched = false;
  for (size_t k = 0; k < n; ++k) {
    const Eigen::Affine3d m = SkinMatrix(mesh, world, k);
    ARMATURE_RETURN_IF_ERROR(CheckFinite(m, k));
    const Eigen::Matrix3d l = m.linear();
    Eigen::Matrix3d rotation = l;
    Eigen::Matrix3d stretch = Eigen::Matrix3d::Identity();
    const bool rigid =
        (l.transpose() * l - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-5 && l.determinant() > 0;
    if (!rigid) {  // polar decomposition L = R·S, a reflection carried by S
      rotation = NearestRotation(l.transpose());
      stretch = rotation.transpose() * l;
      *stretched = true;
    }
    const Eigen::Quaterniond real = Eigen::Quaterniond(rotation).normalized();
    const Eigen::Vector3d t = m.translation();
    const Eigen::Quaterniond dual = Eigen::Quaterniond(0, 0.5 * t.x(), 0.5 * t.y(), 0.5 * t.z()) * real;
    for (int i = 0; i < 4; ++i) {
      ws.dual_quaternions[k].q[i] = static_cast<float>(real.coeffs()[i]);
      ws.dual_quaternions[k].q[4 + i] = static_cast<float>(dual.coeffs()[i]);
    }
    StoreColumns(stretch, Eigen::Vector3d::Zero(), ws.stretch[k]);
  }
  // Each (heaviest joint, joint) pair's dual quaternion, negated when its
  // rotation is in the other hemisphere from the heaviest joint's.
  const auto& pairs = mesh.layout.pairs;
  Grow(ws.pair_dual_quaternions, pairs.size());
  for (size_t p = 0; p < pairs.size(); ++p) {
    const float* pivot = ws.dual_quaternions[pairs[p].first].q;
    const float* joint = ws.dual_quaternions[pairs[p].second].q;
    float dot = 0;
    for (int i = 0; i < 4; ++i) dot += pivot[i] * joint[i];
    const float sign = dot < 0 ? -1.f : 1.f;
    for (int i = 0; i < 8; ++i) ws.pair_dual_quaternions[p].q[i] = sign * joint[i];
  }
  return Status::Ok();
}

// Copies rest geometry of runtime vertices [begin, end) into `out` (six SoA
// arrays) and adds the weighted sparse deltas of every active target.
void MorphRange(const SkinningLayout& l, std::span<const float> weights, bool normals, float* const out[6],
                uint32_t begin, uint32_t end) {
  const size_t bytes = sizeof(float) * (end - begin);
  const float* const rest[6] = {l.x.data(), l.y.data(), l.z.data(), l.nx.data(), l.ny.data(), l.nz.data()};
  for (int c = 0; c < (normals ? 6 : 3); ++c) std::memcpy(out[c] + begin, rest[c] + begin, bytes);
  for (size_t t = 0; t < l.targets.size(); ++t) {
    const float w = weights[t];
    if (w == 0) continue;
    const SkinningLayout::Target& target = l.targets[t];
    const bool target_normals = normals && !target.nx.empty();
    size_t i = static_cast<size_t>(std::lower_bound(target.vertices.begin(), target.vertices.end(), begin) -
                                   target.vertices.begin());
    for (; i < target.vertices.size() && target.vertices[i] < end; ++i) {
      const uint32_t r = target.vertices[i];
      out[0][r] += w * target.dx[i], out[1][r] += w * target.dy[i], out[2][r] += w * target.dz[i];
      if (target_normals) out[3][r] += w * target.nx[i], out[4][r] += w * target.ny[i], out[5][r] += w * target.nz[i];
    }
  }
}

}  // namespace

Status CheckOutputs(const Mesh* mesh, std::span<const float> morph_weights, std::span<float> positions,
                    std::span<float> normals, const SkinningWorkspace* workspace) {
  if (mesh == nullptr) return Status::InvalidArgument("no mesh");
  if (workspace == nullptr) return Status::InvalidArgument("no workspace");
  const size_t n = mesh->vertex_count();
  if (mesh->layout.order.size() != n)
    return Status::FailedPrecondition("mesh '" + mesh->name + "' was not finalized (FinalizeMesh)");
  if (positions.size() != 3 * n)
    return Status::InvalidArgument("positions: expected " + std::to_string(3 * n) + " floats, got " +
                                   std::to_string(positions.size()));
  if (!normals.empty() && normals.size() != 3 * n)
    return Status::InvalidArgument("normals: expected " + std::to_string(3 * n) + " floats, got " +
                                   std::to_string(normals.size()));
  if (!normals.empty() && mesh->normals.empty())
    return Status::InvalidArgument("normals requested but mesh '" + mesh->name + "' has none");
  if (!morph_weights.empty() && morph_weights.size() != mesh->targets.size())
    return Status::InvalidArgument("morph_weights: expected " + std::to_string(mesh->targets.size()) +
                                   " (one per target), got " + std::to_string(morph_weights.size()));
  for (size_t t = 0; t < morph_weights.size(); ++t)
    if (!std::isfinite(morph_weights[t]))
      return Status::InvalidArgument("morph_weights[" + std::to_string(t) + "] is not finite");
  return Status::Ok();
}

// Morphs then skins (or copies), in chunks of the runtime vertex range.
Status RunVertexPipeline(const VertexPipeline& d) {
  const Mesh& mesh = *d.mesh;
  const SkinningLayout& l = mesh.layout;
  const size_t n = mesh.vertex_count();
  const bool normals = !d.normals.empty();
  SkinningWorkspace& ws = *d.ws;

  KernelInput in;
  in.groups = l.groups.data();
  in.group_count = l.groups.size();
  in.order = l.order.data();
  in.joints = l.joints.data();
  in.weights = l.weights.data();
  in.method = d.method;
  in.skin = d.skin && mesh.skinned();
  in.positions = d.positions.data();
  in.normals = normals ? d.normals.data() : nullptr;
  if (in.skin) {
    if (d.method == SkinningMethod::kLinear) {
      bool normal_matrices = false;
      ARMATURE_RETURN_IF_ERROR(PrepareLinear(mesh, d.joint_world, normals, ws, &normal_matrices));
      in.matrices = ws.matrices.data()->c;
      in.normal_matrices = normal_matrices ? ws.normal_matrices.data()->c : nullptr;
    } else {
      bool stretched = false;
      ARMATURE_RETURN_IF_ERROR(PrepareDualQuaternion(mesh, d.joint_world, ws, &stretched));
      in.dual_quaternions = ws.pair_dual_quaternions.data()->q;
      in.pair_offsets = l.pair_offsets.data();
      in.stretch = stretched ? ws.stretch.data()->c : nullptr;
    }
  }

  const std::span<const float> weights =
      d.morph_weights.empty() ? std::span<const float>(mesh.default_weights) : d.morph_weights;
  const bool morph = std::any_of(weights.begin(), weights.end(), [](float w) { return w != 0; });
  bool normal_morph = false;
  for (size_t t = 0; t < l.targets.size(); ++t) normal_morph |= weights[t] != 0 && !l.targets[t].nx.empty();
  in.unit_normals = !normal_morph;  // the layout's rest normals are unit
  float* morphed[6] = {};
  if (morph) {
    Grow(ws.morphed, 6 * n);
    for (int c = 0; c < 6; ++c) morphed[c] = ws.morphed.data() + c * n;
    in.x = morphed[0], in.y = morphed[1], in.z = morphed[2];
    if (normals) in.nx = morphed[3], in.ny = morphed[4], in.nz = morphed[5];
  } else {
    in.x = l.x.data(), in.y = l.y.data(), in.z = l.z.data();
    if (normals) in.nx = l.nx.data(), in.ny = l.ny.data(), in.nz = l.nz.data();
  }

  WorkerPool* pool = d.parallel && n >= kParallelVertices ? &WorkerPool::Shared() : nullptr;
  ParallelRanges(pool, n, 2, [&](size_t first, size_t last) {
    const auto begin = static_cast<uint32_t>(first), end = static_cast<uint32_t>(last);
    if (morph) MorphRange(l, weights, normals, morphed, begin, end);
    skinning_internal::SkinRange(in, begin, end);
  });
  return Status::Ok();
}

}  // namespace armature::skinning_internal
