// Shared by the IK integration tests: the rigs (real motion and the joints pulled on), the
// rig's skeleton and poses read over the API, effectors, and the IkApi fixture.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "armature/client.h"
#include "support/server_process.h"

namespace armature::testing {

// A clip of real motion and the joints the tests pull on.
struct Rig {
  std::string clip;  // also the skeleton's name
  std::string hand, foot;
  std::string arm_root;       // CCD/FABRIK: the arm chain hangs below this joint
  std::vector<double> times;  // target frames (seconds)
  double start_shift;         // the start frame is this much later
};

inline const Rig kDemoRig = {"demo_walk", "LeftWrist", "RightAnkle", "Chest", {0.2, 0.7, 1.3, 2.1}, 0.45};
inline const Rig kCmuRig = {"cmu", "LeftHand", "RightFoot", "LeftShoulder", {2.0, 6.5, 11.0, 16.0}, 1.7};

inline Eigen::Vector3d At3(const google::protobuf::RepeatedField<float>& v, int joint) {
  return {v[3 * joint], v[3 * joint + 1], v[3 * joint + 2]};
}

// The index of joint `name` of `skeleton` (a test failure and 0 when it has none).
inline int JointIndex(const v1::Skeleton& skeleton, const std::string& name) {
  for (int j = 0; j < skeleton.joints_size(); ++j)
    if (skeleton.joints(j).name() == name) return j;
  ADD_FAILURE() << "no joint " << name;
  return 0;
}

// The skeleton and poses of one rig, read over the API.
class Motion {
 public:
  Motion(client::Client& client, const Rig& rig) : client_(client), rig_(rig), skeleton_(client.GetSkeleton(rig.clip)) {
    for (int j = 0; j < skeleton_.joints_size(); ++j) index_[skeleton_.joints(j).name()] = j;
  }

  int Joint(const std::string& name) const { return index_.at(name); }
  int Parent(int joint) const { return skeleton_.joints(joint).parent(); }
  const v1::Skeleton& skeleton() const { return skeleton_; }

  v1::Pose Pose(double time, v1::Space space) const {
    v1::EvaluateClipRequest r;
    r.set_clip(rig_.clip);
    r.add_times(time);
    r.set_space(space);
    return client_.EvaluateClip(r).poses(0);
  }
  Eigen::Vector3d WorldPosition(double time, const std::string& joint) const {
    return At3(Pose(time, v1::WORLD).translations(), Joint(joint));
  }

  // Bone lengths from `joint` up to `top` (the highest joint that moves).
  double ChainLength(const std::string& joint, int top) const {
    double length = 0;
    for (int j = Joint(joint); j != top && j >= 0; j = Parent(j)) {
      const auto& o = skeleton_.joints(j).offset();
      length += Eigen::Vector3d(o[0], o[1], o[2]).norm();
    }
    return length;
  }

  // World position of `joint` under the local `pose`, by the server's
  // forward kinematics (ComputeFk), not the IK engine's.
  Eigen::Vector3d Fk(const v1::Pose& local, const std::string& joint) const {
    v1::ComputeFkRequest r;
    r.set_skeleton(rig_.clip);
    *r.mutable_pose()->mutable_rotations() = local.rotations();
    *r.mutable_pose()->mutable_translations() = local.translations();
    return At3(client_.ComputeFk(r).world().translations(), Joint(joint));
  }

 private:
  client::Client& client_;
  const Rig& rig_;
  v1::Skeleton skeleton_;
  std::map<std::string, int> index_;
};

// `base` with the rotations of `moved` joints taken from `other`: a start
// pose that differs from `base` exactly on those joints.
inline v1::Pose MixPose(const v1::Pose& base, const v1::Pose& other, const std::vector<int>& moved) {
  v1::Pose out = base;
  out.clear_scales();
  for (int j : moved)
    for (int k = 0; k < 4; ++k) out.set_rotations(4 * j + k, other.rotations(4 * j + k));
  return out;
}

inline v1::IkEffector Effector(const std::string& joint, const Eigen::Vector3d& target) {
  v1::IkEffector e;
  e.set_joint(joint);
  for (int k = 0; k < 3; ++k) e.add_target_position(target[k]);
  return e;
}

class IkApi : public ::testing::Test {
 protected:
  TempDir data_;
};

}  // namespace armature::testing
