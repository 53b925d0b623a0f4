// CreateClip's bake on a server at its default --clip-error: the baked clip
// is held compressed like an import, so at its key times it is the motion's
// pose within the stated bound, measured as the bound is stated (points 3 cm
// from each joint along its local axes, in world space, 0.01 cm apart at
// most). `precision` asks for another bound or exact; keys alone stay exact.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "armature/client.h"
#include "authoring/create_clip_support.h"
#include "support/client_helpers.h"
#include "support/server_suite.h"

namespace armature::testing {
namespace {

constexpr double kBoundCm = 0.01;  // the server's default --clip-error
constexpr double kShellCm = 3.0;   // the demo skeleton is in centimetres
// The poses come back as floats: a root 330 cm from the origin is rounded
// to 3e-5 cm, and each virtual point's rotation to about 1e-7 rad.
constexpr double kFloatRoundingCm = 1e-4;

class CreateClipBakeAtTheDefaultBound : public ServerSuite {
 protected:
  static void SetUpTestSuite() {
    data_ = new TempDir;
    server_ = new ServerProcess(data_->path(), {});
  }
};

// Two walks blended, the second at a third of the weight.
v1::Motion Blend() { return TwoWalksBlend(1.0 / 3); }

// The farthest any joint's virtual point moves between two world poses.
double WorstShellDisplacement(const v1::Pose& a, const v1::Pose& b) {
  double worst = 0;
  for (int j = 0; j < a.rotations_size() / 4; ++j) {
    auto rotation = [j](const v1::Pose& p) {
      return Eigen::Quaterniond(p.rotations(4 * j), p.rotations(4 * j + 1), p.rotations(4 * j + 2),
                                p.rotations(4 * j + 3))
          .normalized();
    };
    auto position = [j](const v1::Pose& p) {
      return Eigen::Vector3d(p.translations(3 * j), p.translations(3 * j + 1), p.translations(3 * j + 2));
    };
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3d point = kShellCm * Eigen::Vector3d::Unit(axis);
      const Eigen::Vector3d pa = rotation(a) * point + position(a), pb = rotation(b) * point + position(b);
      worst = std::max(worst, (pa - pb).norm());
    }
  }
  return worst;
}

TEST_F(CreateClipBakeAtTheDefaultBound, BakedKeysAreTheMotionsPosesWithinTheBound) {
  client::Client client(OptionsFor(*server_));
  v1::CreateClipRequest request;
  request.set_name("baked");
  *request.mutable_bake()->mutable_motion() = Blend();
  request.mutable_bake()->set_fps(30);
  request.mutable_bake()->set_duration(2.5);
  const auto made = client.CreateClip(request);
  ASSERT_EQ(made.clip().frames(), 76);  // 0, 1/30, …, 2.5
  for (const std::string& w : made.warnings()) ADD_FAILURE() << "warning: " << w;

  const v1::ClipInfo info = client.GetClip("baked");
  EXPECT_FALSE(info.exact());
  EXPECT_EQ(info.error_bound_cm(), kBoundCm);
  EXPECT_LE(info.worst_error_cm(), kBoundCm);

  v1::EvaluateMotionRequest motion;
  *motion.mutable_motion() = Blend();
  motion.set_space(v1::WORLD);
  v1::EvaluateClipRequest clip;
  clip.set_clip("baked");
  clip.set_space(v1::WORLD);
  for (int k = 0; k < 76; ++k) {
    motion.add_times(k / 30.0);
    clip.add_times(k / 30.0);
  }
  const auto want = client.EvaluateMotion(motion);
  const auto got = client.EvaluateClip(clip);
  ASSERT_EQ(got.poses_size(), want.poses_size());
  double worst = 0;
  for (int i = 0; i < got.poses_size(); ++i) {
    ASSERT_EQ(got.poses(i).rotations_size(), want.poses(i).rotations_size());
    const double d = WorstShellDisplacement(got.poses(i), want.poses(i));
    worst = std::max(worst, d);
    EXPECT_LE(d, kBoundCm + kFloatRoundingCm) << "key " << i;
  }
  // Compressed: the bake is not the motion bit for bit.
  EXPECT_GT(worst, 1e-4);
  std::printf("[ measured ] baked at the default bound vs the motion: worst %.3g cm (bound %.3g cm; listed %.3g)\n",
              worst, kBoundCm, info.worst_error_cm());
}

TEST_F(CreateClipBakeAtTheDefaultBound, PrecisionIsAskedForOrExactForKeysAlone) {
  client::Client client(OptionsFor(*server_));
  v1::CreateClipRequest request;
  request.set_name("baked_exact");
  *request.mutable_bake()->mutable_motion() = Blend();
  request.mutable_bake()->set_duration(0.5);
  request.set_precision("exact");
  client.CreateClip(request);
  EXPECT_TRUE(client.GetClip("baked_exact").exact());

  request.set_name("baked_coarse");
  request.set_precision("0.5");
  client.CreateClip(request);
  const v1::ClipInfo coarse = client.GetClip("baked_coarse");
  EXPECT_FALSE(coarse.exact());
  EXPECT_EQ(coarse.error_bound_cm(), 0.5);
  EXPECT_LE(coarse.worst_error_cm(), 0.5);

  v1::CreateClipRequest keys;  // authored keys, no bake: held as given
  keys.set_skeleton("demo_walk");
  keys.set_name("keyed");
  v1::JointKeys* head = keys.add_tracks();
  head->set_joint("Head");
  for (double t : {0.0, 0.5}) {
    head->add_times(t);
    for (double v : {1.0, 0.0, 0.0, 0.0}) head->add_rotations(v);
  }
  client.CreateClip(keys);
  EXPECT_TRUE(client.GetClip("keyed").exact());

  for (const char* bad : {"0", "-1", "nan", "11", "fine"}) {
    request.set_name("never");
    request.set_precision(bad);
    const grpc::Status status = StatusOf([&] { client.CreateClip(request); });
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << bad;
    EXPECT_NE(status.error_message().find("precision"), std::string::npos) << status.error_message();
  }
  EXPECT_EQ(StatusOf([&] { client.GetClip("never"); }).error_code(), grpc::StatusCode::NOT_FOUND);
}

}  // namespace
}  // namespace armature::testing
