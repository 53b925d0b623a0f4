#include "armature/engine/anim/compression/clip_keys.h"

#include <vector>

#include "armature/engine/anim/compression/clip_sampling_job.h"

namespace armature {

StatusOr<std::shared_ptr<const Clip>> ClipKeysOf(const CompressedClip& clip) {
  if (clip.exact()) return clip.exact_keys;
  if (!clip.skeleton) return Status::InvalidArgument("clip has no skeleton");
  const size_t joints = clip.skeleton->size(), frames = clip.frames.count;
  auto keys = std::make_shared<Clip>();
  keys->skeleton = clip.skeleton;
  keys->joints.resize(joints);
  for (const CompressedWeights& w : clip.weights) keys->weights.push_back(WeightsKeysOf(w, clip.frames, clip.duration));
  keys->duration = clip.duration;
  keys->frame_time = clip.frames.frame_time;
  keys->frame_count = frames;
  std::vector<double> times(frames);
  for (size_t f = 0; f < frames; ++f) times[f] = clip.frames.Time(f);
  if (frames > 0) times.back() = clip.duration;  // the grid's last frame is the clip's end
  for (size_t j = 0; j < joints; ++j) {
    const uint8_t parts = clip.animated_parts[j];
    JointTrack& track = keys->joints[j];
    if (parts & 1) track.rotation.times = times, track.rotation.values.reserve(frames);
    if (parts & 2) track.translation.times = times, track.translation.values.reserve(frames);
    if (parts & 4) track.scale.times = times, track.scale.values.reserve(frames);
  }
  std::vector<Trs> pose(joints);
  ClipSamplingContext context(clip);
  for (size_t f = 0; f < frames; ++f) {
    ARMATURE_RETURN_IF_ERROR((ClipSamplingJob{&clip, times[f], WrapMode::kClamp, &context, pose, {}}.Run()));
    for (size_t j = 0; j < joints; ++j) {
      JointTrack& track = keys->joints[j];
      if (!track.rotation.times.empty()) track.rotation.values.push_back(pose[j].rotation.normalized());
      if (!track.translation.times.empty()) track.translation.values.push_back(pose[j].translation);
      if (!track.scale.times.empty()) track.scale.values.push_back(pose[j].scale);
    }
  }
  return std::shared_ptr<const Clip>(std::move(keys));
}

}  // namespace armature
