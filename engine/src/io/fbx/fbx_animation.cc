// FBX animation stacks (assimp's animations) → clips "<name>.<stack>": each
// channel's keys as the joint's translation, rotation and scale tracks.
// assimp has already baked pre- and post-rotations and pivots into the keys.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "armature/base/utf8.h"
#include "fbx_importer.h"

namespace armature::fbx_internal {

namespace {

// Keys → a track in seconds; keys not after the one before are dropped
// (counted in `dropped`). Values are checked finite by `value`.
template <class Key, class Value, class Convert>
Status ReadKeys(const Key* keys, unsigned count, double ticks_per_second, const std::string& where, Track<Value>& track,
                size_t& dropped, Convert convert) {
  if (count > 0 && keys == nullptr) return Status::InvalidArgument(where + ": keys missing");
  track.times.reserve(count);
  track.values.reserve(count);
  for (unsigned k = 0; k < count; ++k) {
    const double t = keys[k].mTime / ticks_per_second;
    if (!std::isfinite(t)) return Status::InvalidArgument(where + ": key " + std::to_string(k) + " has no finite time");
    if (!track.times.empty() && t <= track.times.back()) {
      ++dropped;
      continue;
    }
    ARMATURE_ASSIGN_OR_RETURN(Value v, convert(keys[k].mValue, k));
    track.times.push_back(t);
    track.values.push_back(v);
  }
  track.interpolation = Interpolation::kLinear;
  return Status::Ok();
}

}  // namespace

Status Importer::ImportAnimation(unsigned a) {
  const aiAnimation& anim = *scene_.mAnimations[a];
  std::string stack = anim.mName.C_Str();
  const std::string where = "FBX animation stack " + std::to_string(a) + " '" + EscapeForMessage(stack) + "'";
  if (!IsValidUtf8(stack)) return Status::InvalidArgument(where + ": the name is not valid UTF-8");
  if (stack.rfind("AnimStack::", 0) == 0) stack = stack.substr(11);
  if (!skeleton_) {
    warnings_.push_back(where + " animates no node; left out");
    return Status::Ok();
  }
  // assimp's FBX ticks are frames at the file's rate; 0 would mean "unknown".
  const double ticks_per_second = anim.mTicksPerSecond > 0 ? anim.mTicksPerSecond : 25.0;
  auto clip = std::make_shared<Clip>();
  clip->skeleton = skeleton_;
  clip->joints.resize(skeleton_->size());
  uint64_t total_keys = 0;
  size_t dropped = 0, unknown = 0;
  for (unsigned c = 0; c < anim.mNumChannels; ++c) {
    const aiNodeAnim& channel = *anim.mChannels[c];
    const std::string node = channel.mNodeName.C_Str();
    const int joint = JointNamed(node);
    if (joint < 0) {
      ++unknown;
      continue;
    }
    const std::string at = where + " channel '" + EscapeForMessage(node) + "'";
    for (unsigned count : {channel.mNumPositionKeys, channel.mNumRotationKeys, channel.mNumScalingKeys}) {
      if (count > limits_.max_clip_frames)
        return Status::ResourceExhausted(
            at + ": " + OverImportLimitCount(count, "keys", "max_clip_frames", limits_.max_clip_frames));
      total_keys += count;
    }
    if (total_keys > limits_.max_clip_keys)
      return Status::ResourceExhausted(
          where + ": " + OverImportLimitCount(total_keys, "keys", "max_clip_keys", limits_.max_clip_keys));
    JointTrack& track = clip->joints[static_cast<size_t>(joint)];
    const auto vector = [&](const aiVector3D& v, unsigned k) -> StatusOr<Eigen::Vector3d> {
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        return Status::InvalidArgument(at + ": key " + std::to_string(k) + " is not finite");
      return Eigen::Vector3d(v.x, v.y, v.z);
    };
    const auto rotation = [&](const aiQuaternion& q, unsigned k) -> StatusOr<Eigen::Quaterniond> {
      const Eigen::Quaterniond r(q.w, q.x, q.y, q.z);
      const double norm = r.norm();
      if (!std::isfinite(norm) || norm < 1e-9)
        return Status::InvalidArgument(at + ": rotation key " + std::to_string(k) + " is not a rotation");
      return Eigen::Quaterniond(r.coeffs() / norm);
    };
    ARMATURE_RETURN_IF_ERROR(ReadKeys(channel.mPositionKeys, channel.mNumPositionKeys, ticks_per_second, at,
                                      track.translation, dropped, vector));
    ARMATURE_RETURN_IF_ERROR(ReadKeys(channel.mRotationKeys, channel.mNumRotationKeys, ticks_per_second, at,
                                      track.rotation, dropped, rotation));
    ARMATURE_RETURN_IF_ERROR(
        ReadKeys(channel.mScalingKeys, channel.mNumScalingKeys, ticks_per_second, at, track.scale, dropped, vector));
    for (const auto* times : {&track.translation.times, &track.rotation.times, &track.scale.times}) {
      if (times->empty()) continue;
      clip->duration = std::max(clip->duration, times->back());
      clip->frame_count = std::max(clip->frame_count, times->size());
    }
  }
  if (dropped > 0)
    warnings_.push_back(where + ": " + std::to_string(dropped) + " keys not after the one before dropped");
  if (unknown > 0) warnings_.push_back(where + ": " + std::to_string(unknown) + " channels name no node; left out");
  if (anim.mNumMorphMeshChannels > 0 || anim.mNumMeshChannels > 0)
    warnings_.push_back(where + ": morph weight and mesh animation not imported");
  ARMATURE_RETURN_IF_ERROR(clip->Validate().WithContext(where + ": "));
  const std::string local = used_clip_names_.Take(stack.empty() ? std::to_string(a) : stack);
  contents_.clips.push_back({name_ + "." + local, name_, clip});
  return Status::Ok();
}

}  // namespace armature::fbx_internal
