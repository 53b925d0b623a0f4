// glTF export of a clip: one animation, a sampler and a channel per animated
// joint property and per mesh's morph weights (see gltf_writer.h for the
// interpolation rules).
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "armature/engine/math/rotation.h"
#include "gltf_export.h"

namespace armature::gltf_export {
namespace {

// The step between resampled keys of a CUBIC track without tangents.
double ResampleStep(const Clip& clip) { return clip.frame_time > 0 ? clip.frame_time : 1.0 / 30; }

template <class V>
bool HasTangents(const Track<V>& track) {
  return track.interpolation == Interpolation::kCubic && track.in_tangents.size() == track.values.size() &&
         track.out_tangents.size() == track.values.size();
}

// Keys a CUBIC track without tangents is resampled at: its keys, and between
// two keys as many evenly spaced ones as the step asks for.
uint64_t ResampledKeyCount(const std::vector<double>& times, double step) {
  uint64_t n = times.empty() ? 0 : 1;
  for (size_t k = 1; k < times.size(); ++k) {
    const double parts = std::ceil((times[k] - times[k - 1]) / step);
    n = Add(n, parts >= 1e18 ? UINT64_MAX : static_cast<uint64_t>(std::max(parts, 1.0)));
  }
  return n;
}

std::vector<double> ResampledTimes(const std::vector<double>& times, double step) {
  std::vector<double> out;
  if (times.empty()) return out;
  out.push_back(times[0]);
  for (size_t k = 1; k < times.size(); ++k) {
    const double a = times[k - 1], b = times[k];
    const int parts = static_cast<int>(std::max(1.0, std::ceil((b - a) / step)));
    for (int i = 1; i < parts; ++i) out.push_back(a + (b - a) * i / parts);
    out.push_back(b);
  }
  return out;
}

template <class V>
uint64_t TrackBytes(const Track<V>& track, size_t components, double step) {
  if (track.empty()) return 0;
  uint64_t keys = track.times.size(), per_key = components;
  if (track.interpolation == Interpolation::kCubic) {
    if (HasTangents(track))
      per_key *= 3;
    else
      keys = ResampledKeyCount(track.times, step);
  }
  // times, values, alignment, and the JSON of two accessors, views, a sampler and a channel
  return Add(Mul(keys, 4 * (per_key + 1)), 8 + 6 * kJsonBytesPerObject);
}

class AnimationWriter {
 public:
  AnimationWriter(const Clip& clip, ModelBuilder& builder) : clip_(clip), builder_(builder) {}

  Status AddJoint(size_t j) {
    const JointTrack& track = clip_.joints[j];
    const std::string where = "joint '" + clip_.skeleton->names[j] + "'";
    ARMATURE_RETURN_IF_ERROR(AddVec3(track.translation, j, "translation", where));
    ARMATURE_RETURN_IF_ERROR(AddRotation(track.rotation, j, where));
    return AddVec3(track.scale, j, "scale", where);
  }

  Status AddWeights(const WeightsTrack& track, int node, size_t mesh_targets) {
    const std::string where = "weights of mesh '" + track.mesh + "'";
    if (track.times.empty()) return Status::Ok();
    if (track.targets != mesh_targets)
      return Status::InvalidArgument("glTF export: " + where + " animate " + std::to_string(track.targets) +
                                     " targets, the mesh has " + std::to_string(mesh_targets));
    const size_t n = track.times.size() * track.targets;
    const bool triplets = track.interpolation == Interpolation::kCubic && track.values.size() == 3 * n;
    if (!triplets && track.values.size() != n)
      return Status::InvalidArgument("glTF export: " + where + " has " + std::to_string(track.values.size()) +
                                     " values for " + std::to_string(track.times.size()) + " keys × " +
                                     std::to_string(track.targets) + " targets");
    std::vector<float> values(track.values.size());
    for (size_t i = 0; i < values.size(); ++i) {
      ARMATURE_ASSIGN_OR_RETURN(auto f, ToFloat(track.values[i], "glTF export: " + where));
      values[i] = f;
    }
    // Cubic weights without tangents are written LINEAR at their keys.
    const Interpolation mode = triplets                                      ? Interpolation::kCubic
                               : track.interpolation == Interpolation::kStep ? Interpolation::kStep
                                                                             : Interpolation::kLinear;
    return Channel(track.times, values, TINYGLTF_TYPE_SCALAR, values.size(), mode, node, "weights", where);
  }

  tinygltf::Animation& animation() { return animation_; }

 private:
  static const char* SamplerName(Interpolation mode) {
    return mode == Interpolation::kStep ? "STEP" : mode == Interpolation::kCubic ? "CUBICSPLINE" : "LINEAR";
  }

  Status Channel(const std::vector<double>& times, const std::vector<float>& values, int type, size_t count,
                 Interpolation mode, size_t node, const char* path, const std::string& where) {
    ARMATURE_ASSIGN_OR_RETURN(auto input, builder_.AddTimes(times, "glTF export: " + where + " " + path));
    tinygltf::AnimationSampler sampler;
    sampler.input = input;
    sampler.output = builder_.AddFloats(values, type, count);
    sampler.interpolation = SamplerName(mode);
    animation_.samplers.push_back(std::move(sampler));
    tinygltf::AnimationChannel channel;
    channel.sampler = static_cast<int>(animation_.samplers.size()) - 1;
    channel.target_node = static_cast<int>(node);
    channel.target_path = path;
    animation_.channels.push_back(std::move(channel));
    return Status::Ok();
  }

  Status Append(std::vector<float>& out, std::initializer_list<double> values, const std::string& where) {
    for (double x : values) {
      ARMATURE_ASSIGN_OR_RETURN(auto f, ToFloat(x, "glTF export: " + where));
      out.push_back(f);
    }
    return Status::Ok();
  }

  // The track sampled at `times` through the clip's own sampler: the part
  // `pick` selects of the joint's local transform.
  std::vector<Trs> Resample(const JointTrack& only, const std::vector<double>& times, size_t j) {
    std::vector<Trs> out(times.size(), clip_.skeleton->rest[j]);
    for (size_t k = 0; k < times.size(); ++k) SampleJoint(only, times[k], std::nullopt, out[k]);
    return out;
  }

  Status AddVec3(const Vec3Track& track, size_t j, const char* path, const std::string& where) {
    if (track.empty()) return Status::Ok();
    const bool translation = path[0] == 't';
    const std::string what = where + " " + path;
    std::vector<float> values;
    if (track.interpolation == Interpolation::kCubic && !HasTangents(track)) {
      const std::vector<double> times = ResampledTimes(track.times, ResampleStep(clip_));
      JointTrack only;
      (translation ? only.translation : only.scale) = track;
      for (const Trs& trs : Resample(only, times, j)) {
        const Eigen::Vector3d& v = translation ? trs.translation : trs.scale;
        ARMATURE_RETURN_IF_ERROR(Append(values, {v.x(), v.y(), v.z()}, what));
      }
      return Channel(times, values, TINYGLTF_TYPE_VEC3, times.size(), Interpolation::kLinear, j, path, where);
    }
    const bool cubic = track.interpolation == Interpolation::kCubic;
    for (size_t k = 0; k < track.values.size(); ++k) {
      if (cubic)
        ARMATURE_RETURN_IF_ERROR(
            Append(values, {track.in_tangents[k].x(), track.in_tangents[k].y(), track.in_tangents[k].z()}, what));
      ARMATURE_RETURN_IF_ERROR(Append(values, {track.values[k].x(), track.values[k].y(), track.values[k].z()}, what));
      if (cubic)
        ARMATURE_RETURN_IF_ERROR(
            Append(values, {track.out_tangents[k].x(), track.out_tangents[k].y(), track.out_tangents[k].z()}, what));
    }
    return Channel(track.times, values, TINYGLTF_TYPE_VEC3, values.size() / 3, track.interpolation, j, path, where);
  }

  Status AddRotation(const QuatTrack& track, size_t j, const std::string& where) {
    if (track.empty()) return Status::Ok();
    const std::string what = where + " rotation";
    std::vector<float> values;
    auto append = [&](const Eigen::Quaterniond& q) { return Append(values, {q.x(), q.y(), q.z(), q.w()}, what); };
    if (track.interpolation == Interpolation::kCubic && !HasTangents(track)) {
      const std::vector<double> times = ResampledTimes(track.times, ResampleStep(clip_));
      JointTrack only;
      only.rotation = track;
      Eigen::Quaterniond previous = Eigen::Quaterniond::Identity();
      for (const Trs& trs : Resample(only, times, j)) {
        previous = SameHemisphere(trs.rotation, previous);
        ARMATURE_RETURN_IF_ERROR(append(previous));
      }
      return Channel(times, values, TINYGLTF_TYPE_VEC4, times.size(), Interpolation::kLinear, j, "rotation", where);
    }
    if (track.interpolation == Interpolation::kCubic) {
      // Tangents are relative to the values as they are: no sign change.
      for (size_t k = 0; k < track.values.size(); ++k) {
        ARMATURE_RETURN_IF_ERROR(append(track.in_tangents[k]));
        ARMATURE_RETURN_IF_ERROR(append(track.values[k]));
        ARMATURE_RETURN_IF_ERROR(append(track.out_tangents[k]));
      }
    } else {
      // Consecutive keys in one hemisphere, so any slerp takes the path ours does.
      Eigen::Quaterniond previous = Eigen::Quaterniond::Identity();
      for (const Eigen::Quaterniond& q : track.values) {
        previous = SameHemisphere(q, previous);
        ARMATURE_RETURN_IF_ERROR(append(previous));
      }
    }
    return Channel(track.times, values, TINYGLTF_TYPE_VEC4, values.size() / 4, track.interpolation, j, "rotation",
                   where);
  }

  const Clip& clip_;
  ModelBuilder& builder_;
  tinygltf::Animation animation_;
};

}  // namespace

uint64_t AnimationByteEstimate(const Clip& clip) {
  const double step = ResampleStep(clip);
  uint64_t bytes = kJsonBytesPerObject;
  for (const JointTrack& track : clip.joints) {
    bytes = Add(bytes, TrackBytes(track.translation, 3, step));
    bytes = Add(bytes, TrackBytes(track.rotation, 4, step));
    bytes = Add(bytes, TrackBytes(track.scale, 3, step));
  }
  for (const WeightsTrack& track : clip.weights)
    bytes = Add(bytes, Add(Mul(4, Add(track.times.size(), track.values.size())), 8 + 6 * kJsonBytesPerObject));
  return bytes;
}

Status AddAnimation(const Clip& clip, const std::string& name, const std::map<std::string, int>& mesh_nodes,
                    ModelBuilder& builder) {
  AnimationWriter writer(clip, builder);
  for (size_t j = 0; j < clip.joints.size(); ++j) ARMATURE_RETURN_IF_ERROR(writer.AddJoint(j));
  const tinygltf::Model& model = builder.model();
  for (const WeightsTrack& track : clip.weights) {
    auto node = mesh_nodes.find(track.mesh);
    if (node == mesh_nodes.end()) continue;  // its mesh is not written
    const int mesh = model.nodes[static_cast<size_t>(node->second)].mesh;
    const size_t targets = model.meshes[static_cast<size_t>(mesh)].weights.size();
    ARMATURE_RETURN_IF_ERROR(writer.AddWeights(track, node->second, targets));
  }
  if (writer.animation().channels.empty()) return Status::Ok();  // glTF requires at least one channel
  writer.animation().name = name;
  builder.model().animations.push_back(std::move(writer.animation()));
  return Status::Ok();
}

}  // namespace armature::gltf_export
