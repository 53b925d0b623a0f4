#include "armature/engine/mesh/blendshape.h"

#include <string>
#include <utility>

#include "vertex_pipeline.h"

namespace armature {

using skinning_internal::CheckOutputs;
using skinning_internal::RunVertexPipeline;

Status BlendshapeJob::Validate() const { return CheckOutputs(mesh, weights, positions, normals, workspace); }

Status BlendshapeJob::Run() const {
  ARMATURE_RETURN_IF_ERROR(Validate());
  return RunVertexPipeline(
      {mesh, {}, weights, SkinningMethod::kLinear, false, parallel, positions, normals, workspace});
}

StatusOr<MorphTarget> MorphTargetFromShape(const Mesh& base, std::string name, std::span<const float> positions,
                                           std::span<const float> normals, float tolerance) {
  const size_t n = base.vertex_count();
  if (positions.size() != 3 * n)
    return Status::InvalidArgument("target '" + name + "' positions: expected " + std::to_string(3 * n) +
                                   " floats, got " + std::to_string(positions.size()));
  if (!normals.empty() && (normals.size() != 3 * n || base.normals.size() != n))
    return Status::InvalidArgument("target '" + name + "' normals: expected " + std::to_string(3 * n) +
                                   " floats and a base mesh with normals");
  MorphTarget target;
  target.name = std::move(name);
  for (size_t v = 0; v < n; ++v) {
    const Eigen::Vector3f dp =
        Eigen::Vector3f(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]) - base.positions[v];
    Eigen::Vector3f dn = Eigen::Vector3f::Zero();
    if (!normals.empty())
      dn = Eigen::Vector3f(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]) - base.normals[v];
    if (!dp.allFinite() || !dn.allFinite())
      return Status::InvalidArgument("target '" + target.name + "': vertex " + std::to_string(v) + " is not finite");
    if (dp.cwiseAbs().maxCoeff() <= tolerance && dn.cwiseAbs().maxCoeff() <= tolerance) continue;
    target.vertices.push_back(static_cast<uint32_t>(v));
    target.position_deltas.push_back(dp);
    if (!normals.empty()) target.normal_deltas.push_back(dn);
  }
  return target;
}

}  // namespace armature
