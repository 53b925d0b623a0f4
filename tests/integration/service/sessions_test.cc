// IK and deformation sessions share one admission: the per-client and total
// limits count both kinds together, --max-ik-sessions counts IK alone, and
// armature_sessions_active{kind} counts each kind.
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/testing/generated_meshes.h"
#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/metrics_scrape.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

constexpr int kSide = 9;  // a 9 × 9 sheet: the bottom row fixed, the top row's middle vertex dragged

class Sessions : public ::testing::Test {
 protected:
  // A server with the demo rig (IK) and a generated sheet (deformation).
  void Start(const std::vector<std::string>& flags) {
    server_.emplace(data_.path(), flags);
    client_.emplace(OptionsFor(*server_));
    client_->Import({"sheet.obj", fixtures::ToObj(fixtures::MakeGrid(kSide, kSide, 1, 1))}, "sheet");
    ik_start_.set_skeleton("demo_walk");
    v1::IkEffector* wrist = ik_start_.add_effectors();
    wrist->set_joint("LeftWrist");
    for (double x : {20.0, 30.0, 20.0}) wrist->add_target_position(x);  // within reach of the rest pose
    deform_start_.mutable_setup()->set_mesh("sheet");
    for (uint32_t v = 0; v < kSide; ++v) deform_start_.mutable_setup()->add_fixed(v);
    deform_start_.add_handle_indices(kHandle);
  }

  double Gauge(const char* kind) const {
    return ScrapeSample(*server_, std::string("armature_sessions_active{kind=\"") + kind + "\"}");
  }

  static constexpr uint32_t kHandle = (kSide - 1) * kSide + kSide / 2;
  TempDir data_;
  std::optional<ServerProcess> server_;
  std::optional<client::Client> client_;
  v1::SolveIkRequest ik_start_;
  v1::DeformSessionStart deform_start_;
};

TEST_F(Sessions, OneClientLimitCoversIkAndDeformation) {
  Start({"--max-sessions-per-client", "1"});
  EXPECT_EQ(Gauge("ik"), 0);
  EXPECT_EQ(Gauge("deform"), 0);
  {
    auto ik = client_->OpenIkSession(ik_start_);
    EXPECT_EQ(Gauge("ik"), 1);
    // The open IK session holds this client's one place: a drag session is refused, naming the flag.
    const grpc::Status status = StatusOf([&] { client_->OpenDeformSession(deform_start_); });
    const std::string& message = status.error_message();
    EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_NE(message.find("DeformSession"), std::string::npos) << message;
    EXPECT_NE(message.find("--max-sessions-per-client (1)"), std::string::npos) << message;
    EXPECT_EQ(Gauge("deform"), 0) << "a refused session holds no place";
    ik->Close();
  }
  // Closed (the place is given back before the client hears the end): the drag session fits.
  EXPECT_EQ(Gauge("ik"), 0);
  auto drag = client_->OpenDeformSession(deform_start_);
  ASSERT_EQ(drag->last().positions_size(), 3 * kSide * kSide);
  EXPECT_EQ(Gauge("deform"), 1);
  EXPECT_EQ(Gauge("ik"), 0);
  // And now it is the drag session that holds the place.
  const std::string message = MessageOf([&] { client_->OpenIkSession(ik_start_); });
  EXPECT_NE(message.find("IkSession"), std::string::npos) << message;
  EXPECT_NE(message.find("--max-sessions-per-client (1)"), std::string::npos) << message;
  const std::vector<double> target = {0.1, 0.6, 0.3};
  const v1::DeformResponse& moved = drag->Move(target);
  EXPECT_EQ(moved.index(), 1u);
  for (int a = 0; a < 3; ++a)
    EXPECT_EQ(moved.positions(static_cast<int>(3 * kHandle) + a), static_cast<float>(target[a]));
  drag->Close();
  EXPECT_EQ(Gauge("deform"), 0);
}

TEST_F(Sessions, TotalLimitCoversBothKindsAndTheIkLimitOnlyIk) {
  Start({"--max-sessions", "2", "--max-ik-sessions", "1"});
  auto ik = client_->OpenIkSession(ik_start_);
  // A second IK session is over --max-ik-sessions, though --max-sessions has room.
  const grpc::Status second_ik = StatusOf([&] { client_->OpenIkSession(ik_start_); });
  EXPECT_EQ(second_ik.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(second_ik.error_message().find("--max-ik-sessions (1)"), std::string::npos) << second_ik.error_message();
  // A drag session is not an IK session: it takes the second place in all.
  auto drag = client_->OpenDeformSession(deform_start_);
  EXPECT_EQ(Gauge("ik"), 1);
  EXPECT_EQ(Gauge("deform"), 1);
  // The server is full: a third session of either kind names --max-sessions.
  const grpc::Status third = StatusOf([&] { client_->OpenDeformSession(deform_start_); });
  EXPECT_EQ(third.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(third.error_message().find("--max-sessions (2)"), std::string::npos) << third.error_message();
  ik.reset();  // cancelled: its place comes back once the server has seen the cancellation
  EXPECT_TRUE(WaitFor([&] { return Gauge("ik") == 0; }, 30)) << Gauge("ik");
  auto second_drag = client_->OpenDeformSession(deform_start_);
  EXPECT_EQ(Gauge("deform"), 2);
  second_drag->Close();
  drag->Close();
  EXPECT_EQ(Gauge("deform"), 0);
}

}  // namespace
}  // namespace armature::testing
