// IK keeps the body where it stands unless asked: by default the skeleton
// root (the hips) neither turns nor moves, so reaching with a hand leaves
// the hips and both ankles exactly where the clip has them; freeRoot lets
// the root turn and/or move. Over gRPC, a session, REST and the CLI, on a
// real armature-server with the demo walk.
#include <cstdio>

#include <Eigen/Core>
#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"
#include "ik/ik_rig.h"

namespace armature::testing {
namespace {
using nlohmann::json;

constexpr double kTime = 1.0;
// The README tour's target: in reach of the left arm and spine at 1.0 s.
const Eigen::Vector3d kWristTarget(25, 100, 125);
const char* const kStill[] = {"Hips", "LeftHip", "LeftKnee", "LeftAnkle", "RightHip", "RightKnee", "RightAnkle"};

v1::SolveIkRequest WristReach(const Eigen::Vector3d& target) {
  v1::SolveIkRequest r;
  r.set_skeleton("demo_walk");
  r.mutable_from_clip()->set_clip("demo_walk");
  r.mutable_from_clip()->set_time(kTime);
  *r.add_effectors() = Effector("LeftWrist", target);
  return r;
}

class IkRoot : public ::testing::Test {
 protected:
  void SetUp() override {
    server_ = std::make_unique<ServerProcess>(data_.path());
    client_ = std::make_unique<client::Client>(OptionsFor(*server_));
    skeleton_ = client_->GetSkeleton("demo_walk");
    v1::EvaluateClipRequest r;
    r.set_clip("demo_walk");
    r.add_times(kTime);
    r.set_space(v1::WORLD);
    clip_world_ = client_->EvaluateClip(r).poses(0);
  }
  int Joint(const std::string& name) const {
    for (int j = 0; j < skeleton_.joints_size(); ++j)
      if (skeleton_.joints(j).name() == name) return j;
    ADD_FAILURE() << "no joint " << name;
    return 0;
  }
  // Hips, legs and ankles exactly where the clip has them (the same floats:
  // both poses come out of the same forward kinematics on the same locals).
  void ExpectLegsStill(const v1::Pose& world, const std::string& what) const {
    for (const char* joint : kStill) {
      const int j = Joint(joint);
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(world.translations(3 * j + k), clip_world_.translations(3 * j + k)) << what << " " << joint;
    }
    const int hips = Joint("Hips");
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(world.rotations(4 * hips + k), clip_world_.rotations(4 * hips + k)) << what << " hips rotation";
  }
  double HipsMoved(const v1::Pose& world) const {
    const int hips = Joint("Hips");
    return (At3(world.translations(), hips) - At3(clip_world_.translations(), hips)).norm();
  }

  TempDir data_;
  std::unique_ptr<ServerProcess> server_;
  std::unique_ptr<client::Client> client_;
  v1::Skeleton skeleton_;
  v1::Pose clip_world_;
};

TEST_F(IkRoot, AHandReachLeavesTheHipsAndAnklesWhereTheyStand) {
  const v1::SolveIkRequest r = WristReach(kWristTarget);
  const v1::SolveIkResponse response = client_->SolveIk(r);
  EXPECT_TRUE(response.converged()) << v1::IkStop_Name(response.stop());
  EXPECT_LT(response.residuals(0).position_error(), 0.1);
  ExpectLegsStill(response.world(), "default");
  // The arm and spine did the work: the wrist moved (by how much, printed).
  const int wrist = Joint("LeftWrist");
  const double moved = (At3(response.world().translations(), wrist) - At3(clip_world_.translations(), wrist)).norm();
  EXPECT_GT(moved, 5.0);
  std::printf("  wrist moved %.2f cm in %d iterations; hips moved %.3g\n", moved, response.iterations(),
              HipsMoved(response.world()));

  // ROOT_FIXED says the same as the default.
  v1::SolveIkRequest fixed = r;
  fixed.set_free_root(v1::ROOT_FIXED);
  ExpectLegsStill(client_->SolveIk(fixed).world(), "ROOT_FIXED");

  // A session keeps them too, message after message.
  auto session = client_->OpenIkSession(r);
  for (int i = 1; i <= 5; ++i) {
    const Eigen::Vector3d p = kWristTarget + Eigen::Vector3d(0, i, 2 * i);
    ExpectLegsStill(session->MoveTarget(0, p.x(), p.y(), p.z()).world(), "session message " + std::to_string(i));
  }
  session->Close();
}

// Out of reach of arm and spine while the hips stand; freeRoot brings it in.
TEST_F(IkRoot, FreeRootLetsTheRootTurnAndMove) {
  const Eigen::Vector3d hips = At3(clip_world_.translations(), Joint("Hips"));
  // The spine-to-wrist chain is 93 cm; this is 121 cm from the spine's base.
  const Eigen::Vector3d far = hips + Eigen::Vector3d(20, 10, 120);
  v1::SolveIkRequest r = WristReach(far);
  const v1::SolveIkResponse fixed = client_->SolveIk(r);
  EXPECT_FALSE(fixed.converged());
  ExpectLegsStill(fixed.world(), "unreachable, default");

  r.set_free_root(v1::ROOT_TRANSLATION);
  const v1::SolveIkResponse moved = client_->SolveIk(r);
  EXPECT_TRUE(moved.converged()) << v1::IkStop_Name(moved.stop());
  EXPECT_GT(HipsMoved(moved.world()), 1.0);
  const int h = Joint("Hips");
  for (int k = 0; k < 4; ++k)  // moved, not turned
    EXPECT_EQ(moved.local().rotations(4 * h + k), fixed.local().rotations(4 * h + k));

  r.set_free_root(v1::ROOT_ROTATION_AND_TRANSLATION);
  const v1::SolveIkResponse both = client_->SolveIk(r);
  EXPECT_TRUE(both.converged()) << v1::IkStop_Name(both.stop());
  EXPECT_GT(HipsMoved(both.world()), 1.0);

  // Rotation only: the hips turn about their origin, which stays.
  r = WristReach(kWristTarget);
  r.set_free_root(v1::ROOT_ROTATION);
  const v1::SolveIkResponse turned = client_->SolveIk(r);
  EXPECT_TRUE(turned.converged());
  EXPECT_EQ(HipsMoved(turned.world()), 0.0);
  std::printf("  out of reach: fixed residual %.1f cm; ROOT_TRANSLATION hips moved %.1f cm; both %.1f cm\n",
              fixed.residuals(0).position_error(), HipsMoved(moved.world()), HipsMoved(both.world()));

  // A solver that cannot move the root says so, naming the API's field.
  r.set_solver(v1::TWO_BONE);
  r.mutable_effectors(0)->set_joint("RightAnkle");
  const std::string message = MessageOf([&] { client_->SolveIk(r); });
  EXPECT_EQ(message, "free_root: the two-bone solver turns fixed joints; use dls, ccd or fabrik");
  r.set_solver(v1::CCD);
  r.set_free_root(v1::ROOT_TRANSLATION);
  EXPECT_EQ(MessageOf([&] { client_->SolveIk(r); }), "free_root: only the dls solver translates the root");
}

TEST_F(IkRoot, FreeRootOverRestAndTheCli) {
  httplib::Client http("127.0.0.1", server_->http_port());
  http.set_read_timeout(60);
  const Eigen::Vector3d hips = At3(clip_world_.translations(), Joint("Hips"));
  const Eigen::Vector3d far = hips + Eigen::Vector3d(20, 10, 120);
  json body = {{"fromClip", {{"clip", "demo_walk"}, {"time", kTime}}},
               {"effectors", json::array({{{"joint", "LeftWrist"}, {"targetPosition", {far.x(), far.y(), far.z()}}}})}};
  auto post = [&](const json& b) { return http.Post("/v1/skeletons/demo_walk:solveIk", b.dump(), "application/json"); };
  const auto fixed = post(body);
  ASSERT_TRUE(fixed);
  ASSERT_EQ(fixed->status, 200) << fixed->body;
  EXPECT_EQ(json::parse(fixed->body)["converged"], false);
  body["freeRoot"] = "root_translation";  // enums in any case over REST
  const auto moved = post(body);
  ASSERT_TRUE(moved);
  ASSERT_EQ(moved->status, 200) << moved->body;
  EXPECT_EQ(json::parse(moved->body)["converged"], true);
  body["freeRoot"] = "loose";
  const auto bad = post(body);
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  EXPECT_NE(bad->body.find("free_root"), std::string::npos) << bad->body;
  EXPECT_NE(bad->body.find("ROOT_ROTATION_AND_TRANSLATION"), std::string::npos) << bad->body;

  // The CLI: the default keeps the hips (the first joint printed), --free-root frees them.
  char effector[96];
  std::snprintf(effector, sizeof effector, "LeftWrist=%.9g,%.9g,%.9g", far.x(), far.y(), far.z());
  const std::vector<std::string> args = {"ik",        "demo_walk", "-e", effector, "--from-clip",
                                         "demo_walk", "--time",    "1",  "--json"};
  const auto cli_fixed = RunCli(server_->target(), args);
  ASSERT_EQ(cli_fixed.exit_code, 0) << cli_fixed.err;
  const json jf = json::parse(cli_fixed.out);
  EXPECT_EQ(jf["converged"], false);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(jf["joints"][0]["translation"][k].get<double>(), hips[k], 1e-4) << "hips, default";
  for (const std::string flag : {"--free-root", "--free-root=translation"}) {
    std::vector<std::string> free_args = args;
    free_args.push_back(flag);
    const auto cli_free = RunCli(server_->target(), free_args);
    ASSERT_EQ(cli_free.exit_code, 0) << flag << ": " << cli_free.err;
    const json j = json::parse(cli_free.out);
    EXPECT_EQ(j["converged"], true) << flag;
    const Eigen::Vector3d h(j["joints"][0]["translation"][0].get<double>(),
                            j["joints"][0]["translation"][1].get<double>(),
                            j["joints"][0]["translation"][2].get<double>());
    EXPECT_GT((h - hips).norm(), 1.0) << flag;
  }
  const auto cli_bad = RunCli(server_->target(), {"ik", "demo_walk", "-e", effector, "--free-root=hips"});
  EXPECT_NE(cli_bad.exit_code, 0);
  EXPECT_NE(cli_bad.err.find("expected rotation, translation or both"), std::string::npos) << cli_bad.err;
}

}  // namespace
}  // namespace armature::testing
