// Skinning: deforms a mesh by its skeleton's pose with linear blend skinning
// (LBS) or dual quaternion skinning (DQS), positions and normals, after
// applying morph targets (the order glTF defines). Any number of influences.
//
// Output is world space, the space a glTF viewer shows: for a glTF skin,
// Σ w·world(joint)·inverse_bind·p, ignoring the transform of the node that
// holds the mesh; a glTF mesh without a skin follows its node.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include <Eigen/Geometry>

#include "armature/engine/anim/clip.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/mesh/mesh.h"
#include "armature/engine/anim/skeleton.h"
#include "armature/base/status.h"
#include "armature/engine/math/transform.h"

namespace armature {

enum class SkinningMethod { kLinear, kDualQuaternion };

// Per-request scratch memory. It grows on first use and is reused, so a
// workspace kept per thread makes skinning allocation-free. Not thread-safe:
// one call at a time per workspace. Its members are internal.
struct SkinningWorkspace {
  struct alignas(32) Matrix {  // columns of a 3×4 affine map, 4 floats each
    float c[16];
  };
  struct alignas(32) DualQuaternion {  // (real x y z w, dual x y z w)
    float q[8];
  };
  std::vector<Trs> local;
  std::vector<Eigen::Affine3d> world;
  std::vector<double> sampled_weights;
  std::vector<float> morph_weights;
  std::vector<Matrix> matrices;                       // LBS: world·inverse_bind per skin joint
  std::vector<Matrix> normal_matrices;                // LBS normals when a joint scales non-uniformly
  std::vector<DualQuaternion> dual_quaternions;       // per skin joint
  std::vector<DualQuaternion> pair_dual_quaternions;  // per layout pair, in its heaviest joint's hemisphere
  std::vector<Matrix> stretch;                        // DQS: the scale/shear left of each joint's rotation
  std::vector<float> morphed;                         // morphed rest geometry, 6 SoA arrays of vertex_count
  ClipSamplingContext clip_context;                   // SkinClip's, resized when the clip changes
};

struct SkinningOptions {
  SkinningMethod method = SkinningMethod::kLinear;
  // Morph target weights overriding the clip's animated or the mesh's default
  // weights; empty = do not override. Size = mesh.targets.size().
  std::span<const float> morph_weights;
  // Splits large meshes across the worker threads (both cores).
  bool parallel = true;
};

// The job: inputs as fields, caller-owned output spans.
struct SkinningJob {
  const Mesh* mesh = nullptr;
  // World transform of every skeleton joint (see ComputeWorld); indexed by
  // mesh->joints. May be empty for an unbound mesh.
  std::span<const Eigen::Affine3d> joint_world;
  // Morph weights, one per target; empty = the mesh's default weights.
  std::span<const float> morph_weights;
  SkinningMethod method = SkinningMethod::kLinear;
  bool parallel = true;
  std::span<float> positions;  // out: x,y,z per vertex in mesh vertex order
  std::span<float> normals;    // out: empty, or x,y,z per vertex (unit length); needs mesh normals
  SkinningWorkspace* workspace = nullptr;

  Status Validate() const;
  Status Run() const;  // validates first
};

// Poses `skeleton` with `local` (one Trs per joint, e.g. from PoseFromArrays)
// and skins `mesh` (whose joints index `skeleton`).
Status SkinPose(const Mesh& mesh, const Skeleton& skeleton, std::span<const Trs> local, const SkinningOptions& options,
                std::span<float> positions, std::span<float> normals, SkinningWorkspace& workspace);

// Where and how SkinClip samples its clip: ClipSamplingJob's time, wrap and
// interpolation; `onto` another skeleton with `map` =
// MapJointsByName(*onto, *clip.skeleton) (ClipSamplingOntoJob), or null for
// the clip's own.
struct ClipSkinningTime {
  double time = 0;
  WrapMode wrap = WrapMode::kClamp;
  std::optional<Interpolation> interpolation;
  const Skeleton* onto = nullptr;
  std::span<const int> map;
};

// The one way to skin by a clip: samples `clip` through the sampling job
// (anim/compression/clip_sampling_job.h; the context kept in `workspace`),
// with its weights track whose `mesh` is mesh.name when there is one, and
// skins `mesh`, whose joints index the skeleton sampled.
Status SkinClip(const Mesh& mesh, const CompressedClip& clip, const ClipSkinningTime& at,
                const SkinningOptions& options, std::span<float> positions, std::span<float> normals,
                SkinningWorkspace& workspace);

}  // namespace armature
