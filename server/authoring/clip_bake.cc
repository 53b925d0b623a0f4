#include "server/authoring/clip_bake.h"

#include <cmath>
#include <vector>

#include "armature/engine/anim/motion.h"
#include "armature/engine/math/rotation.h"
#include "server/assets/motion_convert.h"
#include "server/authoring/create_clip_validation.h"

namespace armature::server {

StatusOr<BakedClip> BakeMotion(const Catalog& catalog, const Limits& limits, const v1::ClipBake& bake) {
  const double fps = bake.fps() == 0 ? 30 : bake.fps();
  if (!(fps > 0 && fps <= 1000))
    return Status::InvalidArgument("bake.fps: " + std::to_string(fps) + " is not in (0, 1000]");
  if (!(std::isfinite(bake.duration()) && bake.duration() > 0))
    return Status::InvalidArgument("bake.duration: required, a finite number of seconds > 0");
  const double frames = std::floor(bake.duration() * fps + 1e-9);
  if (frames + 2 > static_cast<double>(limits.max_clip_frames))
    return Status::ResourceExhausted("bake: " + std::to_string(bake.duration()) + " s at " + std::to_string(fps) +
                                     " fps is " + std::to_string(static_cast<int64_t>(frames) + 1) +
                                     "+ keys, over the limit of " + std::to_string(limits.max_clip_frames) +
                                     " (--max-clip-frames)");
  if (bake.motion().layers().empty()) return Status::InvalidArgument("bake.motion: required (give at least one layer)");
  ARMATURE_ASSIGN_OR_RETURN(auto plan, BindMotionProto(catalog, bake.motion(), limits, "bake.motion"));

  // A bake holds no more memory than an upload may: refuse one whose clip
  // (as baked, as a file, as stored) would pass --max-upload-mb before sampling.
  const double memory_bytes = (frames + 2) * static_cast<double>(plan.skeleton->size()) * kBakeBytesPerJointKey;
  if (memory_bytes > static_cast<double>(limits.max_upload_bytes))
    return Status::ResourceExhausted("bake: " + std::to_string(static_cast<int64_t>(frames) + 1) + " keys × " +
                                     std::to_string(plan.skeleton->size()) + " joints would take about " +
                                     std::to_string(static_cast<int64_t>(memory_bytes) >> 20) + " MiB in memory (" +
                                     std::to_string(kBakeBytesPerJointKey) +
                                     " bytes per joint and key: the clip as baked, as a file and as stored), over "
                                     "--max-upload-mb (" +
                                     std::to_string(limits.max_upload_bytes >> 20) + " MiB); lower fps or duration");
  std::vector<double> times;
  for (int64_t k = 0; k <= static_cast<int64_t>(frames); ++k)
    times.push_back(StoredKeyTime(static_cast<double>(k) / fps));
  if (StoredKeyTime(bake.duration()) > times.back()) times.push_back(StoredKeyTime(bake.duration()));

  BakedClip out;
  out.skeleton = catalog.FindClip(bake.motion().layers(0).clip())->part->skeleton_name;
  Clip& clip = out.clip;
  clip.skeleton = plan.skeleton;
  const size_t joints = plan.skeleton->size();
  clip.joints.resize(joints);
  for (JointTrack& t : clip.joints) {
    for (auto* track_times : {&t.rotation.times, &t.translation.times, &t.scale.times}) *track_times = times;
    t.rotation.values.reserve(times.size());  // exactly: doubling growth would hold up to twice the estimate
    t.translation.values.reserve(times.size());
    t.scale.values.reserve(times.size());
  }
  MotionWorkspace workspace;
  workspace.Resize(plan);
  std::vector<Trs> pose(joints);
  bool scaled = false;
  for (double time : times) {
    const BlendMotionJob job{&plan, time, &workspace, pose, nullptr};
    ARMATURE_RETURN_IF_ERROR(job.Run());
    for (size_t j = 0; j < joints; ++j) {
      JointTrack& t = clip.joints[j];
      t.rotation.values.push_back(pose[j].rotation.normalized());
      t.translation.values.push_back(pose[j].translation);
      t.scale.values.push_back(pose[j].scale);
      scaled = scaled || (pose[j].scale - Eigen::Vector3d::Ones()).cwiseAbs().maxCoeff() > 1e-9;
    }
  }
  if (!scaled)
    for (JointTrack& t : clip.joints) t.scale = Vec3Track{};
  clip.duration = times.back();
  clip.frame_count = times.size();
  return out;
}

}  // namespace armature::server
