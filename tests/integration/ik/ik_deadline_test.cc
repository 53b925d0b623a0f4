// One sweep of CCD or FABRIK over a long chain can outlast a short client
// deadline (FABRIK refreshes the chain below each joint it turns), so the
// solvers look at the deadline inside a sweep too: the server ends the call
// soon after the deadline instead of solving on for an answer nobody waits for.
#include <chrono>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

// A straight chain of `joints` joints up +Y, 1/joints long in all.
std::string ChainBvh(int joints) {
  const std::string bone = std::to_string(1.0 / joints);
  std::string bvh =
      "HIERARCHY\nROOT J0\n{\nOFFSET 0 0 0\nCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n";
  for (int i = 1; i < joints; ++i)
    bvh += "JOINT J" + std::to_string(i) + "\n{\nOFFSET 0 " + bone + " 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n";
  bvh += "End Site\n{\nOFFSET 0 " + bone + " 0\n}\n";
  for (int i = 0; i < joints; ++i) bvh += "}\n";
  bvh += "MOTION\nFrames: 1\nFrame Time: 0.1\n";
  for (int c = 0; c < 3 * joints + 3; ++c) bvh += "0 ";
  return bvh + "\n";
}

// Waits (up to 60 s) for the server's log line of a finished SolveIk and
// returns it, or "" when none came.
std::string FinishedSolveLine(const ServerProcess& server) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < until) {
    const std::string log = ReadFile(server.log_file());
    const size_t at = log.find("method=armature.v1.IkService/SolveIk ");
    if (at != std::string::npos) {
      const size_t begin = log.rfind('\n', at) + 1, end = log.find('\n', at);
      return log.substr(begin, end - begin);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return "";
}

void ExpectStopsSoonAfterTheDeadline(v1::IkSolver solver, int joints, int iterations) {
  SCOPED_TRACE(v1::IkSolver_Name(solver));
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo"});
  client::ClientOptions o = OptionsFor(server);
  client::Client setup(o);
  setup.Import({"chain.bvh", ChainBvh(joints)}, "chain");
  // Allowed: 1 effector × `joints` × `iterations` is within --max-ik-work (5,000,000).
  ASSERT_LE(static_cast<int64_t>(joints) * iterations, 5000000);
  v1::SolveIkRequest r;
  r.set_skeleton("chain");
  r.set_solver(solver);
  r.mutable_options()->set_max_iterations(iterations);
  v1::IkEffector* e = r.add_effectors();
  e->set_joint("J" + std::to_string(joints - 1));
  for (double v : {0.6, 0.3, 0.2}) e->add_target_position(v);

  o.timeout = std::chrono::milliseconds(300);
  client::Client client(o);
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(CodeOf([&] { client.SolveIk(r); }), grpc::StatusCode::DEADLINE_EXCEEDED);
  const std::string line = FinishedSolveLine(server);
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_FALSE(line.empty()) << "the server did not end the call within 60 s";
  std::printf("  %s, %d joints: the server ended the call %.2f s after it began: %s\n",
              v1::IkSolver_Name(solver).c_str(), joints, waited, line.c_str());
  // Generous for a loaded machine; before the in-sweep checks one FABRIK
  // sweep over this chain took about 8 s (20,000 joints) on 2 cores.
  EXPECT_LT(waited, 5.0);
  EXPECT_TRUE(line.find("DEADLINE_EXCEEDED") != std::string::npos || line.find("CANCELLED") != std::string::npos)
      << line;
  EXPECT_TRUE(setup.Healthy());
}

TEST(IkDeadline, FabrikStopsInsideASweepOverALongChain) { ExpectStopsSoonAfterTheDeadline(v1::FABRIK, 30000, 160); }

TEST(IkDeadline, CcdStopsSoonAfterTheDeadlineOnALongChain) { ExpectStopsSoonAfterTheDeadline(v1::CCD, 20000, 250); }

}  // namespace
}  // namespace armature::testing
