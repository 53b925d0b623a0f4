// IK over the API on a real armature-server: deadlines and cancellation of long solves
// (the server goes quiet after them), IK sessions over gRPC and REST, and their limits.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include <Eigen/Core>
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "common/sse_events.h"
#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/metrics_scrape.h"
#include "support/server_process.h"
#include "ik/ik_rig.h"
#include "support/process_cpu.h"

namespace armature::testing {
namespace {
using nlohmann::json;

// Whether the server goes quiet (under `limit` CPU seconds in some 1 s
// window) within a generous bound: a solve nobody waits for would keep a
// core busy for minutes, while winding down a cancelled one may take a
// while on a loaded machine. `last` gets the last window's CPU time.
bool ServerGoesQuiet(pid_t pid, double limit, double* last) {
  return WaitFor(
      [&] {
        const double before = CpuSeconds(pid);
        std::this_thread::sleep_for(std::chrono::seconds(1));
        *last = CpuSeconds(pid) - before;
        return *last < limit;
      },
      20);
}

// A solve that would run for many seconds: every end joint pulled far out
// of reach, restarts and iterations allowed without end (the server is
// started with a huge --max-ik-iterations).
v1::SolveIkRequest EndlessSolve() {
  v1::SolveIkRequest r;
  r.set_skeleton("demo_walk");
  int k = 0;
  for (const char* joint : {"LeftWrist", "RightWrist", "LeftToe", "RightToe", "Head"}) {
    v1::IkEffector* e = r.add_effectors();
    e->set_joint(joint);
    for (double v : {5000.0 * (k % 2 ? 1 : -1), 3000.0 * k, 4000.0}) e->add_target_position(v);
    ++k;
  }
  r.mutable_options()->set_max_iterations(100000000);
  r.mutable_options()->set_max_restarts(100000000);
  return r;
}

TEST_F(IkApi, DeadlineStopsTheSolve) {
  ServerProcess server(data_.path(), {"--max-ik-iterations", "100000000", "--max-ik-work", "1000000000000000"});
  client::ClientOptions o = OptionsFor(server);
  o.timeout = std::chrono::milliseconds(300);
  client::Client client(o);
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(CodeOf([&] { client.SolveIk(EndlessSolve()); }), grpc::StatusCode::DEADLINE_EXCEEDED);
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double cpu = 0;
  EXPECT_TRUE(ServerGoesQuiet(server.pid(), 0.3, &cpu)) << "the solve kept running after its deadline: " << cpu;
  std::printf("  deadline 0.3 s: DEADLINE_EXCEEDED after %.3f s; server CPU in a 1 s window after: %.3f s\n", waited,
              cpu);

  // The same through the gateway, with the deadline as grpc-timeout: 504.
  std::string body;
  ASSERT_TRUE(google::protobuf::util::MessageToJsonString(EndlessSolve(), &body).ok());
  httplib::Client http("127.0.0.1", server.http_port());
  const auto rest = http.Post("/v1/skeletons/demo_walk:solveIk", {{"grpc-timeout", "300m"}}, body, "application/json");
  ASSERT_TRUE(rest);
  EXPECT_EQ(rest->status, 504) << rest->body;
  EXPECT_EQ(json::parse(rest->body)["code"], static_cast<int>(grpc::StatusCode::DEADLINE_EXCEEDED));
  double rest_cpu = 0;
  EXPECT_TRUE(ServerGoesQuiet(server.pid(), 0.3, &rest_cpu))
      << "the REST solve kept running after its deadline: " << rest_cpu;
  std::printf("  gateway, grpc-timeout 300m: HTTP %d; server CPU in a 1 s window after: %.3f s\n", rest->status,
              rest_cpu);

  // Cancelling a session mid-solve stops it too (the solver polls the
  // call's cancellation).
  auto stub = v1::IkService::NewStub(client.channel());
  grpc::ClientContext context;
  auto stream = stub->IkSession(&context);
  v1::IkSessionRequest first;
  *first.mutable_start() = EndlessSolve();
  ASSERT_TRUE(stream->Write(first));
  // The solve runs: the server's CPU time keeps growing (however slowly a loaded machine lets it).
  const double before = CpuSeconds(server.pid());
  EXPECT_TRUE(WaitFor([&] { return CpuSeconds(server.pid()) - before > 0.5; }, 30))
      << "the endless solve should keep a core busy until cancelled";
  const double solving = CpuSeconds(server.pid()) - before;
  context.TryCancel();
  v1::SolveIkResponse answer;
  EXPECT_FALSE(stream->Read(&answer));
  EXPECT_EQ(stream->Finish().error_code(), grpc::StatusCode::CANCELLED);
  double after = 0;
  EXPECT_TRUE(ServerGoesQuiet(server.pid(), 0.3, &after))
      << "the session's solve kept running after the cancel: " << after;
  std::printf("  session: server CPU %.3f s while solving, %.3f s in a 1 s window after the cancel\n", solving, after);
  EXPECT_TRUE(client.Healthy());
}

TEST_F(IkApi, SessionFollowsADraggedHand) {
  ServerProcess server(data_.path());
  client::Client client(OptionsFor(server));
  const Motion m(client, kDemoRig);
  const double t = 0.8;
  const Eigen::Vector3d wrist = m.WorldPosition(t, "LeftWrist"), ankle = m.WorldPosition(t, "RightAnkle");
  v1::SolveIkRequest start;
  start.set_skeleton("demo_walk");
  start.mutable_from_clip()->set_clip("demo_walk");
  start.mutable_from_clip()->set_time(t);
  *start.add_effectors() = Effector("LeftWrist", wrist);
  *start.add_effectors() = Effector("RightAnkle", ankle);  // the foot stays planted
  const double bound = 1e-3 * m.ChainLength("LeftWrist", 0);

  auto session = client.OpenIkSession(start);
  EXPECT_TRUE(session->last().converged());
  EXPECT_EQ(session->last().iterations(), 0) << "the start pose already reaches the first targets";
  // The hand dragged at 60 Hz for one second: 30 cm forward and 15 cm up,
  // around a 5 cm circle.
  std::vector<Eigen::Vector3d> path;
  for (int i = 1; i <= 60; ++i) {
    const double s = i / 60.0, a = 2 * M_PI * s;
    path.push_back(wrist + Eigen::Vector3d(5 * std::sin(a), 15 * s + 5 * (1 - std::cos(a)), 30 * s));
  }
  int warm_total = 0, warm_most = 0;
  double worst = 0;
  for (size_t i = 0; i < path.size(); ++i) {
    const Eigen::Vector3d& target = path[i];
    const v1::SolveIkResponse& answer = session->MoveTarget(0, target.x(), target.y(), target.z());
    ASSERT_TRUE(answer.converged()) << "update " << i << ": " << v1::IkStop_Name(answer.stop());
    // The answer is for this update (in order), and the foot stayed.
    const double error = (At3(answer.world().translations(), m.Joint("LeftWrist")) - target).norm();
    EXPECT_LT(error, bound) << "update " << i;
    EXPECT_LT((At3(answer.world().translations(), m.Joint("RightAnkle")) - ankle).norm(), bound) << "update " << i;
    worst = std::max(worst, error);
    warm_total += answer.iterations();
    warm_most = std::max(warm_most, answer.iterations());
  }
  // Warm starts: the same target again needs nothing more from the last
  // pose, and answers with that pose.
  const v1::SolveIkResponse last = session->last();
  const v1::SolveIkResponse& again = session->MoveTarget(0, path.back().x(), path.back().y(), path.back().z());
  EXPECT_TRUE(again.converged());
  EXPECT_EQ(again.iterations(), 0);
  EXPECT_EQ(again.local().SerializeAsString(), last.local().SerializeAsString());
  session->Close();

  // The same targets solved cold, each from the session's start pose.
  int cold_total = 0;
  for (const Eigen::Vector3d& target : path) {
    v1::SolveIkRequest cold = start;
    for (int k = 0; k < 3; ++k) cold.mutable_effectors(0)->set_target_position(k, target[k]);
    const auto answer = client.SolveIk(cold);
    ASSERT_TRUE(answer.converged());
    cold_total += answer.iterations();
  }
  std::printf(
      "  session: 60 updates converged, worst residual %.2e (bound %.2e); iterations per update: mean %.2f, "
      "max %d; the same targets solved cold from the start pose: mean %.2f\n",
      worst, bound, warm_total / 60.0, warm_most, cold_total / 60.0);
  EXPECT_LE(warm_most, 8) << "updates a few millimetres apart should take few iterations from the last pose";
  EXPECT_LT(warm_total, cold_total) << "warm starts should beat cold starts";
}

TEST_F(IkApi, SessionErrorsAndTheSessionLimit) {
  ServerProcess server(data_.path(), {"--max-ik-sessions", "1", "--shutdown-grace", "1"});
  client::Client client(OptionsFor(server));
  const Motion m(client, kDemoRig);
  v1::SolveIkRequest start;
  start.set_skeleton("demo_walk");
  *start.add_effectors() = Effector("LeftWrist", m.WorldPosition(0, "LeftWrist"));
  {
    auto session = client.OpenIkSession(start);
    // A second concurrent session is over the limit of 1.
    const grpc::Status second = StatusOf([&] { client.OpenIkSession(start); });
    std::string message = second.error_message();
    EXPECT_EQ(second.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_NE(message.find("--max-ik-sessions"), std::string::npos) << message;
    // A bad update ends the session with the field named.
    v1::IkSessionRequest update;
    update.add_targets()->set_effector(3);
    message = MessageOf([&] { session->Send(update); });
    EXPECT_NE(message.find("message 1: targets[0].effector"), std::string::npos) << message;
  }
  // The failed session is gone: a new one fits in the limit.
  auto again = client.OpenIkSession(start);
  v1::IkSessionRequest update;
  v1::IkTargetUpdate* target = update.add_targets();
  for (double v : {1.0, double(NAN), 2.0}) target->add_target_position(v);
  EXPECT_EQ(CodeOf([&] { again->Send(update); }), grpc::StatusCode::INVALID_ARGUMENT);
  // A first message without a start, and a bad start, name the field.
  auto stub = v1::IkService::NewStub(client.channel());
  auto first_message_error = [&](const v1::IkSessionRequest& first) {
    grpc::ClientContext context;
    auto stream = stub->IkSession(&context);
    stream->Write(first);
    v1::SolveIkResponse answer;
    EXPECT_FALSE(stream->Read(&answer));
    return stream->Finish();
  };
  v1::IkSessionRequest no_start;
  no_start.add_targets()->add_target_position(1);
  grpc::Status status = first_message_error(no_start);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("start"), std::string::npos) << status.error_message();
  v1::IkSessionRequest bad_start;
  *bad_start.mutable_start() = start;
  bad_start.mutable_start()->mutable_effectors(0)->set_joint("LeftWristt");
  status = first_message_error(bad_start);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("start.effectors[0].joint"), std::string::npos) << status.error_message();
  // A session left open does not hold up shutdown beyond the grace period.
  auto open = client.OpenIkSession(start);
  EXPECT_EQ(server.Stop(SIGTERM, 10), 0) << ReadFile(server.log_file());
  EXPECT_NE(CodeOf([&] { open->MoveTarget(0, 1, 2, 3); }), grpc::StatusCode::OK);
}

// The armature_sessions_active{kind="ik"} gauge of /metrics.
double OpenSessionsGauge(const ServerProcess& server) {
  return ScrapeSample(server, "armature_sessions_active{kind=\"ik\"}");
}

TEST_F(IkApi, SessionsPerClientAndTheGauge) {
  ServerProcess server(data_.path(), {"--max-sessions-per-client", "2"});
  client::Client client(OptionsFor(server));
  v1::SolveIkRequest start;
  start.set_skeleton("demo_walk");
  *start.add_effectors() = Effector("LeftWrist", {20, 30, 20});  // within reach of the rest pose
  EXPECT_EQ(OpenSessionsGauge(server), 0);
  auto a = client.OpenIkSession(start);
  auto b = client.OpenIkSession(start);
  EXPECT_EQ(OpenSessionsGauge(server), 2);
  // A third from the same client (address) is over its limit.
  const grpc::Status third = StatusOf([&] { client.OpenIkSession(start); });
  const std::string& message = third.error_message();
  EXPECT_NE(message.find("--max-sessions-per-client"), std::string::npos) << message;
  EXPECT_EQ(third.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  a->Close();
  a.reset();
  auto c = client.OpenIkSession(start);  // the closed one's place is free again
  EXPECT_TRUE(c->MoveTarget(0, 21, 30, 20).converged());
  b.reset();  // cancelled by the destructor
  c->Close();
  EXPECT_TRUE(WaitFor([&] { return OpenSessionsGauge(server) == 0; }, 30)) << OpenSessionsGauge(server);
}

}  // namespace
}  // namespace armature::testing
