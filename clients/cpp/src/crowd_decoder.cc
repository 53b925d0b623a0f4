#include "armature/crowd_decoder.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "armature/client.h"

namespace armature::client {
namespace {

[[noreturn]] void Malformed(const std::string& what) {
  throw ClientError(grpc::Status(grpc::StatusCode::INTERNAL, "crowd frame: " + what));
}

// 6 bytes of smallest-three → w, x, y, z (crowd.proto's CrowdLayout).
void DecodeRotation(const uint8_t* in, float* wxyz) {
  uint64_t bits = 0;
  for (int i = 0; i < 6; ++i) bits |= static_cast<uint64_t>(in[i]) << (8 * i);
  const int largest = static_cast<int>(bits & 3);
  const double half = std::sqrt(0.5);
  double c[4], sum = 0;
  int shift = 2;
  for (int i = 0; i < 4; ++i) {
    if (i == largest) continue;
    c[i] = static_cast<double>((bits >> shift) & 32767) / 32767 * (2 * half) - half;
    sum += c[i] * c[i];
    shift += 15;
  }
  c[largest] = std::sqrt(std::max(0.0, 1 - sum));
  const double norm = std::sqrt(sum + c[largest] * c[largest]);
  wxyz[0] = static_cast<float>(c[3] / norm);
  for (int i = 0; i < 3; ++i) wxyz[1 + i] = static_cast<float>(c[i] / norm);
}

const uint8_t* ReadVectors(const google::protobuf::RepeatedField<uint32_t>& joints, uint32_t count, const uint8_t* in,
                           float* out) {
  for (uint32_t j : joints) {
    if (j >= count) Malformed("a layout names joint " + std::to_string(j) + " of " + std::to_string(count));
    std::memcpy(out + 3 * j, in, 12);
    in += 12;
  }
  return in;
}

}  // namespace

const v1::CrowdLayout* CrowdDecoder::layout(uint32_t number) const {
  auto found = layouts_.find(number);
  return found == layouts_.end() ? nullptr : &found->second;
}

CrowdPoses CrowdDecoder::Decode(const v1::CrowdFrame& frame) {
  for (const v1::CrowdLayout& l : frame.new_layouts()) layouts_[l.layout()] = l;
  if (frame.layouts_size() != frame.ids_size()) Malformed("ids and layouts differ in count");
  CrowdPoses poses;
  for (uint32_t number : frame.layouts()) {
    const v1::CrowdLayout* l = layout(number);
    if (!l) Malformed("layout " + std::to_string(number) + " never sent");
    poses.joints = std::max(poses.joints, l->joints());
  }
  const size_t n = static_cast<size_t>(frame.ids_size()), joints = poses.joints;
  poses.ids.assign(frame.ids().begin(), frame.ids().end());
  poses.clip_times.assign(frame.clip_times().begin(), frame.clip_times().end());
  poses.rotations.assign(n * joints * 4, 0.0f);
  poses.translations.assign(n * joints * 3, 0.0f);
  poses.scales.assign(n * joints * 3, 1.0f);
  const auto* in = reinterpret_cast<const uint8_t*>(frame.poses().data());
  const uint8_t* end = in + frame.poses().size();
  for (size_t i = 0; i < n; ++i) {
    const v1::CrowdLayout& l = *layout(frame.layouts(static_cast<int>(i)));
    if (static_cast<size_t>(end - in) < l.pose_bytes()) Malformed("poses end early");
    if (l.base_translations_size() != static_cast<int>(3 * l.joints()) ||
        l.base_scales_size() != static_cast<int>(3 * l.joints()))
      Malformed("layout " + std::to_string(l.layout()) + " has no base pose for its joints");
    float* rotations = poses.rotations.data() + i * joints * 4;
    float* translations = poses.translations.data() + i * joints * 3;
    float* scales = poses.scales.data() + i * joints * 3;
    std::copy(l.base_translations().begin(), l.base_translations().end(), translations);
    std::copy(l.base_scales().begin(), l.base_scales().end(), scales);
    const uint8_t* pose = in;
    for (uint32_t j = 0; j < l.joints(); ++j, pose += 6) DecodeRotation(pose, rotations + 4 * j);
    for (uint32_t j = l.joints(); j < joints; ++j) rotations[4 * j] = 1;  // padding: identity
    pose = ReadVectors(l.translated_joints(), l.joints(), pose, translations);
    pose = ReadVectors(l.scaled_joints(), l.joints(), pose, scales);
    if (pose != in + l.pose_bytes()) Malformed("layout " + std::to_string(l.layout()) + "'s pose_bytes disagree");
    in += l.pose_bytes();
  }
  if (in != end) Malformed("more pose bytes than the ids need");
  return poses;
}

}  // namespace armature::client
