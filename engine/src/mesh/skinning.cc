#include "armature/engine/mesh/skinning.h"

#include <string>

#include "armature/engine/kinematics/fk.h"
#include "vertex_pipeline.h"

namespace armature {

using skinning_internal::CheckOutputs;
using skinning_internal::Grow;
using skinning_internal::RunVertexPipeline;

Status SkinningJob::Validate() const {
  ARMATURE_RETURN_IF_ERROR(CheckOutputs(mesh, morph_weights, positions, normals, workspace));
  for (size_t k = 0; k < mesh->joints.size(); ++k)
    if (static_cast<size_t>(mesh->joints[k]) >= joint_world.size())
      return Status::InvalidArgument("mesh '" + mesh->name + "': skin joint " + std::to_string(k) +
                                     " is skeleton joint " + std::to_string(mesh->joints[k]) + " but the pose has " +
                                     std::to_string(joint_world.size()) + " joints");
  return Status::Ok();
}

Status SkinningJob::Run() const {
  ARMATURE_RETURN_IF_ERROR(Validate());
  return RunVertexPipeline({mesh, joint_world, morph_weights, method, true, parallel, positions, normals, workspace});
}

Status SkinPose(const Mesh& mesh, const Skeleton& skeleton, std::span<const Trs> local, const SkinningOptions& options,
                std::span<float> positions, std::span<float> normals, SkinningWorkspace& workspace) {
  if (local.size() != skeleton.size())
    return Status::InvalidArgument("pose has " + std::to_string(local.size()) + " joints, skeleton has " +
                                   std::to_string(skeleton.size()));
  for (size_t i = 0; i < local.size(); ++i)
    if (!local[i].translation.allFinite() || !local[i].rotation.coeffs().allFinite() || !local[i].scale.allFinite())
      return Status::InvalidArgument("pose: joint '" + skeleton.names[i] + "' is not finite");
  Grow(workspace.world, skeleton.size());
  const std::span<Eigen::Affine3d> world(workspace.world.data(), skeleton.size());
  ComputeWorld(skeleton, local, world);
  SkinningJob job;
  job.mesh = &mesh;
  job.joint_world = world;
  job.morph_weights = options.morph_weights;
  job.method = options.method;
  job.parallel = options.parallel;
  job.positions = positions;
  job.normals = normals;
  job.workspace = &workspace;
  return job.Run();
}

namespace {

// Sets workspace.morph_weights to `clip`'s weights track for `mesh` at `time`,
// if it has one and `options` give none; returns the options to skin with.
SkinningOptions WithClipWeights(const Mesh& mesh, const CompressedClip& clip, double time, WrapMode wrap,
                                const std::optional<Interpolation>& interpolation, const SkinningOptions& options,
                                SkinningWorkspace& workspace) {
  SkinningOptions effective = options;
  if (!options.morph_weights.empty() || mesh.targets.empty()) return effective;
  const size_t targets = mesh.targets.size();
  Grow(workspace.sampled_weights, targets);
  Grow(workspace.morph_weights, targets);
  // Wrap by the clip's duration, as the joints are, then sample the track clamped.
  if (!clip.SampleMorphWeights(mesh.name, targets, WrapTime(time, clip.duration, wrap), interpolation,
                               std::span<double>(workspace.sampled_weights.data(), targets)))
    return effective;
  for (size_t i = 0; i < targets; ++i) workspace.morph_weights[i] = static_cast<float>(workspace.sampled_weights[i]);
  effective.morph_weights = std::span<const float>(workspace.morph_weights.data(), targets);
  return effective;
}

}  // namespace

Status SkinClip(const Mesh& mesh, const CompressedClip& clip, const ClipSkinningTime& at,
                const SkinningOptions& options, std::span<float> positions, std::span<float> normals,
                SkinningWorkspace& workspace) {
  if (!clip.skeleton) return Status::InvalidArgument("clip has no skeleton");
  const Skeleton& skeleton = at.onto ? *at.onto : *clip.skeleton;
  Grow(workspace.local, skeleton.size());
  const std::span<Trs> local(workspace.local.data(), skeleton.size());
  if (!workspace.clip_context.Fits(clip)) workspace.clip_context.Resize(clip);
  if (at.onto) {
    ARMATURE_RETURN_IF_ERROR(
        (ClipSamplingOntoJob{&clip, at.map, at.onto, at.time, at.wrap, &workspace.clip_context, local, at.interpolation}
             .Run()));
  } else {
    ARMATURE_RETURN_IF_ERROR(
        (ClipSamplingJob{&clip, at.time, at.wrap, &workspace.clip_context, local, at.interpolation}.Run()));
  }
  const SkinningOptions effective = WithClipWeights(mesh, clip, at.time, at.wrap, at.interpolation, options, workspace);
  return SkinPose(mesh, skeleton, local, effective, positions, normals, workspace);
}

}  // namespace armature
