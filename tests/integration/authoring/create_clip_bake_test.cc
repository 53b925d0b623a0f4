// CreateClip's bake: a motion sampled at a fps into LINEAR keys; the baked
// clip at its key times is the motion's pose, and entries of `tracks`
// replace baked joints.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "authoring/create_clip_support.h"
#include "support/client_helpers.h"
#include "support/server_suite.h"

namespace armature::testing {
namespace {

// The demo clips held exact, so the bake itself is checked against the
// motion to 1e-5 rad, finer than the default bound (0.01 cm at 3 cm, ~3e-3
// rad). create_clip_bake_bound_test checks a bake at the default bound.
class CreateClipBake : public ServerSuite {
 protected:
  static void SetUpTestSuite() {
    data_ = new TempDir;
    server_ = new ServerProcess(data_->path(), {"--clip-error", "exact"});
  }
};

// Two walks blended half and half.
v1::Motion Blend() { return TwoWalksBlend(0.5); }

TEST_F(CreateClipBake, BakedKeysAreTheMotionsPosesAtTheFps) {
  client::Client client(OptionsFor(*server_));
  v1::CreateClipRequest request;
  request.set_name("baked");
  *request.mutable_bake()->mutable_motion() = Blend();
  request.mutable_bake()->set_fps(24);
  request.mutable_bake()->set_duration(1.1);
  const auto made = client.CreateClip(request);
  EXPECT_EQ(made.clip().frames(), 28);  // 0, 1/24, …, 26/24, and 1.1
  EXPECT_NEAR(made.clip().duration(), 1.1, 1e-6);

  std::vector<double> times;
  for (int k = 0; k <= 26; ++k) times.push_back(k / 24.0);
  times.push_back(1.1);
  v1::EvaluateMotionRequest motion;
  *motion.mutable_motion() = Blend();
  motion.set_space(v1::LOCAL);
  v1::EvaluateClipRequest clip;
  clip.set_clip("baked");
  clip.set_space(v1::LOCAL);
  for (double t : times) {
    motion.add_times(t);
    clip.add_times(t);
  }
  const auto want = client.EvaluateMotion(motion);
  const auto got = client.EvaluateClip(clip);
  ASSERT_EQ(got.poses_size(), want.poses_size());
  double worst = 0;
  for (int i = 0; i < got.poses_size(); ++i) {
    const v1::Pose &a = got.poses(i), &b = want.poses(i);
    ASSERT_EQ(a.rotations_size(), b.rotations_size());
    for (int j = 0; j < a.rotations_size() / 4; ++j) {
      const Eigen::Quaterniond qa(a.rotations(4 * j), a.rotations(4 * j + 1), a.rotations(4 * j + 2),
                                  a.rotations(4 * j + 3));
      const Eigen::Quaterniond qb(b.rotations(4 * j), b.rotations(4 * j + 1), b.rotations(4 * j + 2),
                                  b.rotations(4 * j + 3));
      worst = std::max(worst, qa.angularDistance(qb));
      EXPECT_LT(qa.angularDistance(qb), 1e-5) << "time " << times[i] << " joint " << j;
    }
    for (int c = 0; c < a.translations_size(); ++c)
      EXPECT_TRUE(CloseRelative(a.translations(c), b.translations(c), 1e-6)) << "time " << times[i] << " value " << c;
  }
  std::printf("[ measured ] baked keys vs the motion: worst %.3g rad\n", worst);

  // Between keys: the slerp of the two neighbouring keys (LINEAR), so not the motion's pose.
  const auto mid = SampleLocal(client, "baked", "LeftKnee", {0.5 / 24, 0, 1 / 24.0});
  const Eigen::Quaterniond half = mid[1].rotation.slerp(0.5, mid[2].rotation);
  EXPECT_LT(half.angularDistance(mid[0].rotation), 1e-5);
}

TEST_F(CreateClipBake, TracksReplaceBakedJointsAndBadBakesAreNamed) {
  client::Client client(OptionsFor(*server_));
  v1::CreateClipRequest request;
  request.set_name("baked_head");
  *request.mutable_bake()->mutable_motion() = Blend();
  request.mutable_bake()->set_duration(0.5);
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()));
  *request.add_tracks() = Keys("Head", {0, 0.5}, {q, q}, {}, v1::LINEAR);
  request.add_tracks()->set_joint("LeftKnee");  // no times: the baked track is deleted
  const auto made = client.CreateClip(request);
  EXPECT_EQ(made.clip().frames(), 16);  // 30 fps by default: 0 … 15/30
  EXPECT_LT(q.angularDistance(SampleLocal(client, "baked_head", "Head", {0.25})[0].rotation), 1e-6);
  const v1::Skeleton skeleton = client.GetSkeleton(made.clip().skeleton());
  const auto& knee = skeleton.joints(2);
  ASSERT_EQ(knee.name(), "LeftKnee");
  EXPECT_LT(SampleLocal(client, "baked_head", "LeftKnee", {0.25})[0].rotation.angularDistance(Eigen::Quaterniond(
                knee.rest_rotation(0), knee.rest_rotation(1), knee.rest_rotation(2), knee.rest_rotation(3))),
            1e-6);

  struct Bad {
    std::function<void(v1::CreateClipRequest&)> mutate;
    grpc::StatusCode code;
    std::string mention;
  };
  const std::vector<Bad> bad = {
      {[](auto& r) { r.mutable_bake()->set_fps(-1); }, grpc::StatusCode::INVALID_ARGUMENT, "bake.fps"},
      {[](auto& r) { r.mutable_bake()->set_duration(0); }, grpc::StatusCode::INVALID_ARGUMENT, "bake.duration"},
      {[](auto& r) { r.mutable_bake()->set_duration(1e9); }, grpc::StatusCode::RESOURCE_EXHAUSTED, "--max-clip-frames"},
      {[](auto& r) { r.mutable_bake()->set_duration(500000 / 30.0); }, grpc::StatusCode::RESOURCE_EXHAUSTED,
       "--max-upload-mb"},  // under --max-clip-frames, but 500001 keys × 19 joints is a file over 256 MB
      {[](auto& r) { r.mutable_bake()->mutable_motion()->mutable_layers(0)->set_clip("nope"); },
       grpc::StatusCode::NOT_FOUND, "bake.motion.layers[0]"},
      {[](auto& r) { r.set_skeleton("demo_character"); }, grpc::StatusCode::INVALID_ARGUMENT, "demo_walk"},
      {[](auto& r) { r.set_merge(true); }, grpc::StatusCode::INVALID_ARGUMENT, "not with merge"},
  };
  request.set_name("never");
  for (const Bad& b : bad) {
    v1::CreateClipRequest r = request;
    b.mutate(r);
    const grpc::Status status = StatusOf([&] { client.CreateClip(r); });
    EXPECT_EQ(status.error_code(), b.code) << status.error_message();
    EXPECT_NE(status.error_message().find(b.mention), std::string::npos) << status.error_message();
  }
}

}  // namespace
}  // namespace armature::testing
