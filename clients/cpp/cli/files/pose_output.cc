#include "pose_output.h"

#include <cstdio>

namespace armature::cli {

nlohmann::json PoseJointsJson(const v1::Skeleton& skeleton, const google::protobuf::RepeatedField<int32_t>& joints,
                              const v1::Pose& pose) {
  nlohmann::json out = nlohmann::json::array();
  for (int k = 0; k < joints.size(); ++k) {
    const v1::Joint& joint = skeleton.joints(joints[k]);
    nlohmann::json j = {
        {"name", joint.name()},
        {"parent",
         joint.parent() >= 0 ? nlohmann::json(skeleton.joints(joint.parent()).name()) : nlohmann::json(nullptr)},
        {"translation", {pose.translations(3 * k), pose.translations(3 * k + 1), pose.translations(3 * k + 2)}},
        {"rotation",
         {pose.rotations(4 * k), pose.rotations(4 * k + 1), pose.rotations(4 * k + 2), pose.rotations(4 * k + 3)}}};
    if (pose.scales_size() == 3 * joints.size())
      j["scale"] = {pose.scales(3 * k), pose.scales(3 * k + 1), pose.scales(3 * k + 2)};
    out.push_back(std::move(j));
  }
  return out;
}

void PrintPoseTable(const v1::Skeleton& skeleton, const google::protobuf::RepeatedField<int32_t>& joints,
                    const v1::Pose& pose) {
  std::printf("%-24s %-24s %11s %11s %11s %9s %9s %9s %9s\n", "joint", "parent", "tx", "ty", "tz", "qw", "qx", "qy",
              "qz");
  for (int k = 0; k < joints.size(); ++k) {
    const v1::Joint& joint = skeleton.joints(joints[k]);
    const std::string parent = joint.parent() >= 0 ? skeleton.joints(joint.parent()).name() : "-";
    std::printf("%-24s %-24s %11.5f %11.5f %11.5f %9.6f %9.6f %9.6f %9.6f\n", joint.name().c_str(), parent.c_str(),
                pose.translations(3 * k), pose.translations(3 * k + 1), pose.translations(3 * k + 2),
                pose.rotations(4 * k), pose.rotations(4 * k + 1), pose.rotations(4 * k + 2), pose.rotations(4 * k + 3));
  }
}

}  // namespace armature::cli
