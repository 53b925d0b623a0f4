#include "armature/engine/mesh/skinning.h"

#include <string>

#include "armature/engine/anim/compiled_clip.h"
#include "armature/engine/anim/joint_map.h"
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

// Skins `mesh` by a pose of `skeleton` sampled from `clip` (in
// workspace.local), with the clip's morph weights track for the mesh, if
// any, unless options give weights.
Status SkinSampled(const Mesh& mesh, const Skeleton& skeleton, const Clip& clip, double time,
                   const SampleOptions& sample, const SkinningOptions& options, std::span<float> positions,
                   std::span<float> normals, SkinningWorkspace& workspace) {
  SkinningOptions effective = options;
  if (options.morph_weights.empty() && !mesh.targets.empty()) {
    for (const WeightsTrack& track : clip.weights) {
      if (track.mesh != mesh.name || track.targets != mesh.targets.size()) continue;
      Grow(workspace.sampled_weights, track.targets);
      Grow(workspace.morph_weights, track.targets);
      // Wrap by the clip's duration, as the joints are, then sample the track clamped.
      SampleOptions clamped = sample;
      clamped.wrap = WrapMode::kClamp;
      SampleWeights(track, WrapTime(time, clip.duration, sample.wrap), clamped,
                    std::span<double>(workspace.sampled_weights.data(), track.targets));
      for (size_t i = 0; i < track.targets; ++i)
        workspace.morph_weights[i] = static_cast<float>(workspace.sampled_weights[i]);
      effective.morph_weights = std::span<const float>(workspace.morph_weights.data(), track.targets);
      break;
    }
  }
  const std::span<const Trs> local(workspace.local.data(), skeleton.size());
  return SkinPose(mesh, skeleton, local, effective, positions, normals, workspace);
}

}  // namespace

Status SkinClip(const Mesh& mesh, const Clip& clip, double time, const SampleOptions& sample,
                const SkinningOptions& options, std::span<float> positions, std::span<float> normals,
                SkinningWorkspace& workspace) {
  if (!clip.skeleton) return Status::InvalidArgument("clip has no skeleton");
  const Skeleton& skeleton = *clip.skeleton;
  Grow(workspace.local, skeleton.size());
  ARMATURE_RETURN_IF_ERROR(SampleClip(clip, time, sample, std::span<Trs>(workspace.local.data(), skeleton.size())));
  return SkinSampled(mesh, skeleton, clip, time, sample, options, positions, normals, workspace);
}

Status SkinClip(const Mesh& mesh, const CompiledClip& compiled, double time, const SampleOptions& sample,
                const SkinningOptions& options, std::span<float> positions, std::span<float> normals,
                SkinningWorkspace& workspace) {
  if (!compiled.source || !compiled.source->skeleton) return Status::InvalidArgument("clip has no skeleton");
  const Skeleton& skeleton = *compiled.source->skeleton;
  Grow(workspace.local, skeleton.size());
  ARMATURE_RETURN_IF_ERROR(
      SampleCompiledClip(compiled, time, sample, std::span<Trs>(workspace.local.data(), skeleton.size())));
  return SkinSampled(mesh, skeleton, *compiled.source, time, sample, options, positions, normals, workspace);
}

Status SkinClipOnto(const Mesh& mesh, const Skeleton& skeleton, std::span<const int> map, const Clip& clip, double time,
                    const SampleOptions& sample, const SkinningOptions& options, std::span<float> positions,
                    std::span<float> normals, SkinningWorkspace& workspace) {
  Grow(workspace.local, skeleton.size());
  ARMATURE_RETURN_IF_ERROR(
      SampleClipOnto(clip, map, skeleton, time, sample, std::span<Trs>(workspace.local.data(), skeleton.size())));
  return SkinSampled(mesh, skeleton, clip, time, sample, options, positions, normals, workspace);
}

}  // namespace armature
