// IK requests are bounded before the solve: effectors (--max-ik-effectors)
// and effectors × chain joints × iterations (--max-ik-work).
#include <string>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

v1::SolveIkRequest ArmRequest(int effectors, int iterations) {
  v1::SolveIkRequest r;
  r.set_skeleton("arm");
  r.set_solver(v1::DLS);
  r.set_free_root(v1::ROOT_ROTATION);  // Base, the arm's only turning joint, is its root
  r.mutable_options()->set_max_iterations(iterations);
  for (int i = 0; i < effectors; ++i) {
    v1::IkEffector* e = r.add_effectors();
    e->set_joint("Tip");
    for (double v : {2.0, 3.0, 3.0}) e->add_target_position(v);
  }
  return r;
}

TEST(IkLimits, EffectorsOverTheLimitAreRefusedNamingTheFlag) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-ik-effectors", "8"});
  client::Client client(OptionsFor(server));
  client.Import({"arm.bvh", kArmBvh});
  const grpc::Status refused = StatusOf([&] { client.SolveIk(ArmRequest(9, 50)); });
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << refused.error_message();
  EXPECT_NE(refused.error_message().find("--max-ik-effectors"), std::string::npos) << refused.error_message();
  EXPECT_NE(refused.error_message().find("9 effectors"), std::string::npos) << refused.error_message();
  EXPECT_EQ(StatusOf([&] { client.SolveIk(ArmRequest(8, 50)); }).error_code(), grpc::StatusCode::OK);
}

TEST(IkLimits, WorkOverTheLimitIsRefusedNamingTheFlag) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-ik-work", "1000"});
  client::Client client(OptionsFor(server));
  client.Import({"arm.bvh", kArmBvh});
  // Tip's chain is Tip and Base: 2 effectors × 2 joints × 300 iterations = 1200.
  const grpc::Status refused = StatusOf([&] { client.SolveIk(ArmRequest(2, 300)); });
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << refused.error_message();
  EXPECT_NE(refused.error_message().find("--max-ik-work"), std::string::npos) << refused.error_message();
  EXPECT_NE(refused.error_message().find("1200"), std::string::npos) << refused.error_message();
  EXPECT_EQ(StatusOf([&] { client.SolveIk(ArmRequest(2, 250)); }).error_code(), grpc::StatusCode::OK);
}

}  // namespace
}  // namespace armature::testing
