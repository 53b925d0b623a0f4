#include "armature/engine/anim/joint_map.h"

#include <cmath>
#include <string>

namespace armature {
namespace {

constexpr size_t kNamedMissing = 5;  // joints a mismatch names before "and N more"

}  // namespace

Status MapJointsByName(const Skeleton& target, const Skeleton& source, std::string_view target_label,
                       std::vector<int>& out) {
  out.resize(target.size());
  if (&target == &source) {
    for (size_t j = 0; j < out.size(); ++j) out[j] = static_cast<int>(j);
    return Status::Ok();
  }
  size_t missing = 0;
  std::string named;
  for (size_t j = 0; j < target.size(); ++j) {
    out[j] = source.Find(target.names[j]);
    if (out[j] >= 0) continue;
    if (missing++ < kNamedMissing) named += (named.empty() ? "'" : ", '") + target.names[j] + "'";
  }
  if (missing == 0) return Status::Ok();
  if (missing > kNamedMissing) named += " and " + std::to_string(missing - kNamedMissing) + " more";
  return Status::InvalidArgument("lacks " + std::to_string(missing) + " of the " + std::to_string(target.size()) +
                                 " joints of " + std::string(target_label) + ": " + named);
}

Status SampleClipOnto(const Clip& clip, std::span<const int> map, const Skeleton& target, double time,
                      const SampleOptions& options, std::span<Trs> out) {
  if (!clip.skeleton) return Status::InvalidArgument("clip has no skeleton");
  if (map.size() != target.size() || out.size() != target.size())
    return Status::InvalidArgument("joint map of " + std::to_string(map.size()) + " and output of " +
                                   std::to_string(out.size()) + " for a skeleton of " + std::to_string(target.size()) +
                                   " joints");
  // SampleClip's checks.
  if (clip.joints.size() != clip.skeleton->size())
    return Status::InvalidArgument("clip has " + std::to_string(clip.joints.size()) +
                                   " joint tracks, the skeleton has " + std::to_string(clip.skeleton->size()) +
                                   " joints");
  if (!std::isfinite(time)) return Status::InvalidArgument("time is not finite");
  if (options.interpolation && *options.interpolation != Interpolation::kStep &&
      *options.interpolation != Interpolation::kLinear && *options.interpolation != Interpolation::kCubic)
    return Status::InvalidArgument("sample options: interpolation " +
                                   std::to_string(static_cast<int>(*options.interpolation)) +
                                   " is not STEP, LINEAR or CUBIC");
  if (options.wrap != WrapMode::kClamp && options.wrap != WrapMode::kLoop)
    return Status::InvalidArgument("sample options: wrap mode " + std::to_string(static_cast<int>(options.wrap)) +
                                   " is not CLAMP or LOOP");
  const double t = WrapTime(time, clip.duration, options.wrap);
  for (size_t j = 0; j < target.size(); ++j) {
    const int c = map[j];
    if (c < 0 || c >= static_cast<int>(clip.joints.size()))
      return Status::InvalidArgument("joint map: entry " + std::to_string(j) + " is not a joint of the clip");
    out[j] = target.rest[j];
    SampleJoint(clip.joints[c], t, options.interpolation, out[j]);
  }
  return Status::Ok();
}

}  // namespace armature
