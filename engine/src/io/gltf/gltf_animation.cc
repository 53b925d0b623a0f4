// glTF animations → clips: samplers become joint tracks (STEP, LINEAR,
// CUBICSPLINE) and morph-weight tracks.
#include "gltf_importer.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace armature::gltf_internal {
namespace {

// The clip's own interpolation, as ClipInfo reports it: the one its joint
// tracks share (a CUBICSPLINE clip is CUBIC), LINEAR when they differ or
// there are none.
Interpolation SharedInterpolation(const Clip& clip) {
  std::set<Interpolation> seen;
  auto note = [&seen](const auto& track) {
    if (!track.empty()) seen.insert(track.interpolation);
  };
  for (const JointTrack& t : clip.joints) note(t.translation), note(t.rotation), note(t.scale);
  return seen.size() == 1 ? *seen.begin() : Interpolation::kLinear;
}

// The sampler's interpolation: LINEAR (also when empty), STEP or CUBICSPLINE.
StatusOr<Interpolation> SamplerInterpolation(const tinygltf::AnimationSampler& sampler, const std::string& swhere) {
  if (sampler.interpolation == "LINEAR" || sampler.interpolation.empty()) return Interpolation::kLinear;
  if (sampler.interpolation == "STEP") return Interpolation::kStep;
  if (sampler.interpolation == "CUBICSPLINE") return Interpolation::kCubic;
  return Status::InvalidArgument(swhere + ".interpolation '" + sampler.interpolation +
                                 "' is not LINEAR, STEP or CUBICSPLINE");
}

// A sampler's decoded output: `components` floats per element, and per key
// one element, or for CUBICSPLINE three (in-tangent, value, out-tangent).
struct SamplerOutput {
  const std::vector<float>& values;
  size_t components;
  bool cubic;
  const float* Element(size_t key, size_t part) const {
    return values.data() + (key * (cubic ? 3 : 1) + part) * components;
  }
};

Status FillRotationTrack(const std::vector<double>& times, const SamplerOutput& output, Interpolation interpolation,
                         const std::string& swhere, int accessor, QuatTrack& track) {
  track = QuatTrack{};
  track.times = times;
  track.interpolation = interpolation;
  auto quat = [](const float* p) { return Eigen::Quaterniond(p[3], p[0], p[1], p[2]); };
  for (size_t k = 0; k < times.size(); ++k) {
    Eigen::Quaterniond q = quat(output.Element(k, output.cubic ? 1 : 0));
    if (q.norm() < 1e-6)
      return Status::InvalidArgument(swhere + ".output: accessor " + std::to_string(accessor) + " key " +
                                     std::to_string(k) + " is a zero quaternion");
    track.values.push_back(q.normalized());
    if (output.cubic) {
      track.in_tangents.push_back(quat(output.Element(k, 0)));
      track.out_tangents.push_back(quat(output.Element(k, 2)));
    }
  }
  return Status::Ok();
}

void FillVec3Track(const std::vector<double>& times, const SamplerOutput& output, Interpolation interpolation,
                   Vec3Track& track) {
  track = Vec3Track{};
  track.times = times;
  track.interpolation = interpolation;
  auto vec = [](const float* p) { return Eigen::Vector3d(p[0], p[1], p[2]); };
  for (size_t k = 0; k < times.size(); ++k) {
    track.values.push_back(vec(output.Element(k, output.cubic ? 1 : 0)));
    if (output.cubic) {
      track.in_tangents.push_back(vec(output.Element(k, 0)));
      track.out_tangents.push_back(vec(output.Element(k, 2)));
    }
  }
}

// A later weights channel of the same mesh replaces the earlier one.
void SetWeightsTrack(WeightsTrack track, Clip& clip) {
  auto same = std::find_if(clip.weights.begin(), clip.weights.end(),
                           [&](const WeightsTrack& w) { return w.mesh == track.mesh; });
  if (same != clip.weights.end())
    *same = std::move(track);
  else
    clip.weights.push_back(std::move(track));
}

}  // namespace

Status Importer::ImportAnimation(size_t a) {
  const tinygltf::Animation& anim = model_.animations[a];
  const std::string where = "animations[" + std::to_string(a) + "]";
  if (!skeleton_) return Status::InvalidArgument(where + ": the file has no nodes to animate");
  auto clip = std::make_shared<Clip>();
  clip_keys_ = 0;
  clip->skeleton = skeleton_;
  clip->joints.resize(skeleton_->size());
  clip->default_interpolation = Interpolation::kLinear;
  std::set<std::pair<int, std::string>> animated;
  for (size_t c = 0; c < anim.channels.size(); ++c) {
    const tinygltf::AnimationChannel& channel = anim.channels[c];
    const std::string cwhere = where + ".channels[" + std::to_string(c) + "]";
    if (channel.target_node < 0) {
      warnings_.push_back(cwhere + " has no target node; ignored");
      continue;
    }
    if (static_cast<size_t>(channel.target_node) >= model_.nodes.size())
      return Status::InvalidArgument(cwhere + ".target.node: node " + std::to_string(channel.target_node) +
                                     " does not exist (file has " + std::to_string(model_.nodes.size()) + ")");
    const std::string& path = channel.target_path;
    if (path != "translation" && path != "rotation" && path != "scale" && path != "weights") {
      warnings_.push_back(cwhere + ".target.path '" + path + "' is not supported; ignored");
      continue;
    }
    if (channel.sampler < 0 || static_cast<size_t>(channel.sampler) >= anim.samplers.size())
      return Status::InvalidArgument(cwhere + ".sampler: sampler " + std::to_string(channel.sampler) +
                                     " does not exist (animation has " + std::to_string(anim.samplers.size()) + ")");
    if (!animated.insert({channel.target_node, path}).second)
      warnings_.push_back(cwhere + " animates node " + std::to_string(channel.target_node) + " " + path +
                          " again; the later channel wins");
    ARMATURE_RETURN_IF_ERROR(
        ImportChannel(anim, channel, where + ".samplers[" + std::to_string(channel.sampler) + "]", *clip));
  }
  clip->default_interpolation = SharedInterpolation(*clip);
  ARMATURE_RETURN_IF_ERROR(clip->Validate().WithContext(where + ": "));
  ARMATURE_RETURN_IF_ERROR(CheckName(anim.name, where + ".name"));
  const std::string local = used_clip_names_.Take(anim.name.empty() ? std::to_string(a) : anim.name);
  contents_.clips.push_back({name_ + "." + local, name_, clip});
  return Status::Ok();
}

// Keys before decoding: per sampler, and summed over the clip's tracks; then
// the times, which must increase.
StatusOr<std::vector<double>> Importer::ReadKeyTimes(const tinygltf::AnimationSampler& sampler,
                                                     const std::string& swhere) {
  ARMATURE_ASSIGN_OR_RETURN(const size_t declared, reader_.Count(sampler.input, swhere + ".input"));
  if (declared > limits_.max_clip_frames)
    return Status::ResourceExhausted(
        swhere + ".input: accessor " + std::to_string(sampler.input) + ": " +
        OverImportLimit("key count", declared, "max_clip_frames", limits_.max_clip_frames));
  if (__builtin_add_overflow(clip_keys_, declared, &clip_keys_)) clip_keys_ = UINT64_MAX;
  if (clip_keys_ > limits_.max_clip_keys)
    return Status::ResourceExhausted(
        swhere +
        ".input: " + OverImportLimit("keys of the clip's tracks", clip_keys_, "max_clip_keys", limits_.max_clip_keys));
  // Memory before decoding: a key's time (decoded float, kept double) and its
  // output elements (decoded floats, kept as up to four doubles).
  ARMATURE_ASSIGN_OR_RETURN(const size_t outputs, reader_.Count(sampler.output, swhere + ".output"));
  uint64_t decoded = 0;
  if (__builtin_mul_overflow(outputs, uint64_t{16 + 32}, &decoded) ||
      __builtin_add_overflow(decoded, declared * 12, &decoded))
    decoded = UINT64_MAX;
  ARMATURE_RETURN_IF_ERROR(ChargeDecoded(decoded, swhere));
  std::vector<float> input;
  ARMATURE_RETURN_IF_ERROR(
      reader_.ReadFloats(sampler.input, swhere + ".input", AccessorType::kScalar, {}, &input).status());
  std::vector<double> times(input.begin(), input.end());
  for (size_t k = 1; k < times.size(); ++k)
    if (!(times[k] > times[k - 1]))
      return Status::InvalidArgument(swhere + ".input: accessor " + std::to_string(sampler.input) + " key " +
                                     std::to_string(k) + " time " + std::to_string(times[k]) + " does not increase");
  return times;
}

Status Importer::ImportChannel(const tinygltf::Animation& anim, const tinygltf::AnimationChannel& channel,
                               const std::string& swhere, Clip& clip) {
  const tinygltf::AnimationSampler& sampler = anim.samplers[static_cast<size_t>(channel.sampler)];
  ARMATURE_ASSIGN_OR_RETURN(const Interpolation interpolation, SamplerInterpolation(sampler, swhere));
  const bool cubic = interpolation == Interpolation::kCubic;
  ARMATURE_ASSIGN_OR_RETURN(const std::vector<double> times, ReadKeyTimes(sampler, swhere));
  const size_t keys = times.size();

  // The output's elements: per path, their type, and how many per key.
  const std::string& path = channel.target_path;
  const size_t node = static_cast<size_t>(channel.target_node);
  size_t per_key = cubic ? 3 : 1;
  AccessorType type = AccessorType::kVec3;
  std::initializer_list<int> normalized = {};
  static constexpr std::initializer_list<int> kNormalizedInts = {kByte, kUnsignedByte, kShort, kUnsignedShort};
  int mesh = -1;
  if (path == "rotation") {
    type = AccessorType::kVec4;
    normalized = kNormalizedInts;
  } else if (path == "weights") {
    type = AccessorType::kScalar;
    normalized = kNormalizedInts;
    mesh = model_.nodes[node].mesh;
    if (mesh < 0)
      return Status::InvalidArgument(swhere + ": weights channel targets node " + std::to_string(node) +
                                     ", which has no mesh");
    if (instance_[static_cast<size_t>(mesh)] != static_cast<int>(node)) {
      warnings_.push_back(swhere + ": weights of a second instance of mesh " + std::to_string(mesh) + "; ignored");
      return Status::Ok();
    }
    per_key *= ImportedMesh(mesh).targets.size();
  }
  std::vector<float> output;
  ARMATURE_ASSIGN_OR_RETURN(const AccessorData out,
                            reader_.ReadFloats(sampler.output, swhere + ".output", type, normalized, &output));
  if (out.count != keys * per_key)
    return Status::InvalidArgument(
        swhere + ".output: accessor " + std::to_string(sampler.output) + " has " + std::to_string(out.count) +
        " elements, expected " + std::to_string(keys * per_key) + " (" + std::to_string(keys) + " keys" +
        (cubic ? " × 3 for CUBICSPLINE" : "") +
        (mesh >= 0 ? " × " + std::to_string(ImportedMesh(mesh).targets.size()) + " targets" : std::string()) + ")");
  clip.duration = std::max(clip.duration, times.back());
  clip.frame_count = std::max(clip.frame_count, keys);

  if (mesh >= 0) {
    WeightsTrack track;
    track.mesh = ImportedMesh(mesh).name;
    track.targets = ImportedMesh(mesh).targets.size();
    track.times = times;
    track.values.assign(output.begin(), output.end());
    track.interpolation = interpolation;
    SetWeightsTrack(std::move(track), clip);
    return Status::Ok();
  }
  JointTrack& joint = clip.joints[static_cast<size_t>(joint_of_[node])];
  const SamplerOutput elements{output, out.components, cubic};
  if (path == "rotation")
    return FillRotationTrack(times, elements, interpolation, swhere, sampler.output, joint.rotation);
  FillVec3Track(times, elements, interpolation, path == "translation" ? joint.translation : joint.scale);
  return Status::Ok();
}

}  // namespace armature::gltf_internal
