// Inverse kinematics over the API, end to end on a real armature-server:
// targets taken from real motion (the CMU capture when present, the demo
// walk always) are reached from other start poses with one and two
// effectors, through the client library and the CLI; unreachable targets
// and bad input. Deadlines and sessions are in ik_session_test.cc.
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

namespace armature::testing {
namespace {
using nlohmann::json;

// Every effector reached: converged, the server's residuals and an
// independent FK of the returned pose within 1e-3 × each chain's length.
void ExpectReached(const Motion& motion, const v1::SolveIkRequest& request, const v1::SolveIkResponse& response,
                   const std::vector<double>& chain_lengths, const std::string& what) {
  EXPECT_TRUE(response.converged()) << what << ": stop " << v1::IkStop_Name(response.stop());
  EXPECT_EQ(response.stop(), v1::STOP_CONVERGED) << what;
  ASSERT_EQ(response.residuals_size(), request.effectors_size()) << what;
  ASSERT_EQ(response.joints_size(), motion.skeleton().joints_size()) << what;
  for (int i = 0; i < request.effectors_size(); ++i) {
    const v1::IkEffector& e = request.effectors(i);
    const Eigen::Vector3d target(e.target_position(0), e.target_position(1), e.target_position(2));
    const double bound = 1e-3 * chain_lengths[i];
    const double fk_error = (motion.Fk(response.local(), e.joint()) - target).norm();
    const double world_error = (At3(response.world().translations(), motion.Joint(e.joint())) - target).norm();
    EXPECT_EQ(response.residuals(i).joint(), e.joint());
    EXPECT_TRUE(response.residuals(i).reached()) << what << " " << e.joint();
    EXPECT_LT(response.residuals(i).position_error(), bound) << what << " " << e.joint();
    EXPECT_LT(fk_error, bound) << what << " " << e.joint() << " (FK of the returned local pose)";
    EXPECT_LT(world_error, bound) << what << " " << e.joint() << " (the returned world pose)";
    std::printf("  %-44s %-11s iterations %3d restarts %d residual %.2e  fk %.2e  (bound %.2e)\n", what.c_str(),
                e.joint().c_str(), response.iterations(), response.restarts(), response.residuals(i).position_error(),
                fk_error, bound);
  }
}

// The solves for one rig: DLS with one and two effectors from another
// frame and from the rest pose, two-bone on a leg, CCD and FABRIK on an arm.
void SolveMocapTargets(client::Client& client, const Rig& rig) {
  const Motion m(client, rig);
  const int root = 0;
  const int hand = m.Joint(rig.hand), foot = m.Joint(rig.foot);
  const double hand_chain = m.ChainLength(rig.hand, root), foot_chain = m.ChainLength(rig.foot, root);
  std::vector<int> all(m.skeleton().joints_size());
  for (int j = 0; j < static_cast<int>(all.size()); ++j) all[j] = j;
  v1::Pose rest_rotations;  // for the rest-pose start
  for (const v1::Joint& j : m.skeleton().joints())
    for (float v : j.rest_rotation()) rest_rotations.add_rotations(v);

  for (double t : rig.times) {
    const double t_start = t + rig.start_shift;
    const v1::Pose target_local = m.Pose(t, v1::LOCAL), start_local = m.Pose(t_start, v1::LOCAL);
    const Eigen::Vector3d hand_target = m.WorldPosition(t, rig.hand), foot_target = m.WorldPosition(t, rig.foot);
    const std::string frames = rig.clip + " t=" + std::to_string(t).substr(0, 4);

    // DLS over every joint above the effectors, starting from another
    // frame's joint rotations (placed at the target frame's root, so the
    // targets are within reach), then from the rest pose.
    for (const bool from_rest : {false, true}) {
      v1::SolveIkRequest r;
      r.set_skeleton(rig.clip);
      *r.mutable_start_pose() = MixPose(target_local, from_rest ? rest_rotations : start_local, all);
      *r.add_effectors() = Effector(rig.hand, hand_target);
      const std::string start = from_rest ? " from rest" : " from t+" + std::to_string(rig.start_shift).substr(0, 4);
      ExpectReached(m, r, client.SolveIk(r), {hand_chain}, frames + " dls 1 effector" + start);
      *r.add_effectors() = Effector(rig.foot, foot_target);
      ExpectReached(m, r, client.SolveIk(r), {hand_chain, foot_chain}, frames + " dls 2 effectors" + start);
    }

    // Two-bone on the leg: hip and knee start from the other frame.
    {
      const int knee = m.Parent(foot), hip = m.Parent(knee);
      v1::SolveIkRequest r;
      r.set_skeleton(rig.clip);
      r.set_solver(v1::TWO_BONE);
      *r.mutable_start_pose() = MixPose(target_local, start_local, {hip, knee});
      *r.add_effectors() = Effector(rig.foot, foot_target);
      ExpectReached(m, r, client.SolveIk(r), {m.ChainLength(rig.foot, hip)}, frames + " two-bone leg");
    }

    // CCD and FABRIK on the arm below arm_root.
    for (const v1::IkSolver solver : {v1::CCD, v1::FABRIK}) {
      std::vector<int> chain;
      for (int j = m.Parent(hand); j != m.Joint(rig.arm_root); j = m.Parent(j)) chain.push_back(j);
      v1::SolveIkRequest r;
      r.set_skeleton(rig.clip);
      r.set_solver(solver);
      r.set_root(rig.arm_root);
      r.mutable_options()->set_max_iterations(1000);
      *r.mutable_start_pose() = MixPose(target_local, start_local, chain);
      *r.add_effectors() = Effector(rig.hand, hand_target);
      ExpectReached(m, r, client.SolveIk(r), {m.ChainLength(rig.hand, chain.back())},
                    frames + (solver == v1::CCD ? " ccd arm" : " fabrik arm"));
    }
  }
}

TEST_F(IkApi, DemoWalkTargetsAreReached) {
  ServerProcess server(data_.path());
  client::Client client(OptionsFor(server));
  SolveMocapTargets(client, kDemoRig);
}

TEST_F(IkApi, CmuCaptureTargetsAreReached) {
  const std::string cmu = SharedData("bvh/cmu_01_01.bvh");
  if (cmu.empty()) GTEST_SKIP() << "../shared/data/bvh/cmu_01_01.bvh not present";
  ServerProcess server(data_.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  client.ImportFile(cmu, "cmu");
  SolveMocapTargets(client, kCmuRig);
}

TEST_F(IkApi, FromClipStartAndUnreachableTarget) {
  ServerProcess server(data_.path());
  client::Client client(OptionsFor(server));
  const Motion m(client, kDemoRig);
  // Start from the clip itself: the wrist where it is 0.1 s later.
  v1::SolveIkRequest r;
  r.set_skeleton("demo_walk");
  r.mutable_from_clip()->set_clip("demo_walk");
  r.mutable_from_clip()->set_time(0.5);
  *r.add_effectors() = Effector("LeftWrist", m.WorldPosition(0.6, "LeftWrist"));
  const auto reached = client.SolveIk(r);
  ExpectReached(m, r, reached, {m.ChainLength("LeftWrist", 0)}, "demo_walk from_clip t=0.5 → wrist at 0.6");
  EXPECT_GT(reached.iterations(), 0);

  // Far out of reach: the best effort, not an error.
  const Eigen::Vector3d hips = m.WorldPosition(0.5, "Hips");
  r.mutable_effectors(0)->clear_target_position();
  for (double v : {hips.x() + 1000, hips.y(), hips.z()}) r.mutable_effectors(0)->add_target_position(v);
  const auto best = client.SolveIk(r);
  EXPECT_FALSE(best.converged());
  EXPECT_NE(best.stop(), v1::STOP_CONVERGED);
  EXPECT_FALSE(best.residuals(0).reached());
  // The best effort points the arm at the target: the wrist ends up a full
  // chain (spine to wrist: the hips stay where they stand) closer to it than
  // the spine's base is.
  const Eigen::Vector3d target(hips.x() + 1000, hips.y(), hips.z());
  const double distance =
      (target - m.WorldPosition(0.5, "Spine")).norm() - m.ChainLength("LeftWrist", m.Joint("Spine"));
  EXPECT_NEAR(best.residuals(0).position_error(), distance, 1e-2 * distance);
}

TEST_F(IkApi, ThroughTheCli) {
  ServerProcess server(data_.path());
  client::Client client(OptionsFor(server));
  const Motion m(client, kDemoRig);
  const Eigen::Vector3d wrist = m.WorldPosition(1.1, "LeftWrist"), ankle = m.WorldPosition(1.1, "RightAnkle");
  auto arg = [](const std::string& joint, const Eigen::Vector3d& p) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s=%.9g,%.9g,%.9g", joint.c_str(), p.x(), p.y(), p.z());
    return std::string(buf);
  };
  // One and two effectors, starting from the clip 0.1 s earlier.
  for (int effectors : {1, 2}) {
    std::vector<std::string> args = {"ik",          "demo_walk", "--effector", arg("LeftWrist", wrist),
                                     "--from-clip", "demo_walk", "--time",     "1.0",
                                     "--json"};
    if (effectors == 2) args.insert(args.begin() + 4, {"--effector", arg("RightAnkle", ankle)});
    const auto out = RunCli(server.target(), args);
    ASSERT_EQ(out.exit_code, 0) << out.err;
    const json j = json::parse(out.out);
    EXPECT_EQ(j["skeleton"], "demo_walk");
    EXPECT_EQ(j["space"], "world");
    EXPECT_EQ(j["converged"], true);
    ASSERT_EQ(j["joints"].size(), static_cast<size_t>(m.skeleton().joints_size()));
    EXPECT_TRUE(j["joints"][0]["parent"].is_null());
    ASSERT_EQ(j["residuals"].size(), static_cast<size_t>(effectors));
    const std::pair<std::string, Eigen::Vector3d> targets[] = {{"LeftWrist", wrist}, {"RightAnkle", ankle}};
    for (int i = 0; i < effectors; ++i) {
      const auto& [joint, target] = targets[i];
      const json& residual = j["residuals"][i];
      EXPECT_EQ(residual["joint"], joint);
      EXPECT_EQ(residual["reached"], true);
      const double bound = 1e-3 * m.ChainLength(joint, 0);
      EXPECT_LT(residual["positionError"].get<double>(), bound);
      const json& printed = j["joints"][m.Joint(joint)];
      EXPECT_EQ(printed["name"], joint);
      const Eigen::Vector3d p(printed["translation"][0].get<double>(), printed["translation"][1].get<double>(),
                              printed["translation"][2].get<double>());
      EXPECT_LT((p - target).norm(), bound) << joint;
      std::printf("  cli %d effector(s) %-10s residual %.2e printed %.2e (bound %.2e) iterations %d\n", effectors,
                  joint.c_str(), residual["positionError"].get<double>(), (p - target).norm(), bound,
                  j["iterations"].get<int>());
    }
  }
  // Unreachable: converged false, exit 0.
  const auto far = RunCli(server.target(), {"ik", "demo_walk", "-e", "LeftWrist=0,5000,0", "--json"});
  ASSERT_EQ(far.exit_code, 0) << far.err;
  const json f = json::parse(far.out);
  EXPECT_EQ(f["converged"], false);
  EXPECT_EQ(f["residuals"][0]["reached"], false);
  // The table form, and a two-bone solve.
  const auto table =
      RunCli(server.target(), {"ik", "demo_walk", "--solver", "two-bone", "-e", arg("RightAnkle", ankle)});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("converged"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("RightAnkle"), std::string::npos) << table.out;
  // Bad input: the server's message, non-zero exit.
  const auto bad = RunCli(server.target(), {"ik", "demo_walk", "-e", "LeftWristt=0,1,0"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("INVALID_ARGUMENT"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("effectors[0].joint"), std::string::npos) << bad.err;
  const auto malformed = RunCli(server.target(), {"ik", "demo_walk", "-e", "LeftWrist=0,1"});
  EXPECT_NE(malformed.exit_code, 0);
  EXPECT_NE(malformed.err.find("JOINT=x,y,z"), std::string::npos) << malformed.err;
}

json Xyz(const Eigen::Vector3d& p) { return json::array({p.x(), p.y(), p.z()}); }

// A JSON pose (proto3 JSON of v1::Pose) against the gRPC one, float by float.
void ExpectSamePose(const json& rest, const v1::Pose& grpc, const std::string& what) {
  for (const auto& [key, field] :
       {std::pair{"translations", &grpc.translations()}, std::pair{"rotations", &grpc.rotations()}}) {
    ASSERT_EQ(rest[key].size(), static_cast<size_t>(field->size())) << what << " " << key;
    for (int i = 0; i < field->size(); ++i)
      EXPECT_FLOAT_EQ(static_cast<float>(rest[key][i].get<double>()), (*field)[i])
          << what << " " << key << "[" << i << "]";
  }
}

TEST_F(IkApi, ThroughTheGateway) {
  ServerProcess server(data_.path());
  client::Client client(OptionsFor(server));
  httplib::Client http("127.0.0.1", server.http_port());
  http.set_read_timeout(60);
  const Motion m(client, kDemoRig);
  const double t = 1.6;
  const Eigen::Vector3d wrist = m.WorldPosition(t, "LeftWrist"), ankle = m.WorldPosition(t, "RightAnkle");
  // What a browser or curl sends: targets from the clip at t, the start
  // from the clip 0.1 s earlier; one effector, then two. The hips have moved
  // on by then: the ankle is only in reach when they may turn.
  json body = {{"fromClip", {{"clip", "demo_walk"}, {"time", t - 0.1}}},
               {"freeRoot", "ROOT_ROTATION"},
               {"effectors", json::array({{{"joint", "LeftWrist"}, {"targetPosition", Xyz(wrist)}}})}};
  for (int effectors : {1, 2}) {
    if (effectors == 2) body["effectors"].push_back({{"joint", "RightAnkle"}, {"targetPosition", Xyz(ankle)}});
    const auto r = http.Post("/v1/skeletons/demo_walk:solveIk", body.dump(), "application/json");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    const json rest = json::parse(r->body);
    EXPECT_EQ(rest["converged"], true) << r->body.substr(0, 300);
    EXPECT_EQ(rest["stop"], "STOP_CONVERGED");
    ASSERT_EQ(rest["residuals"].size(), static_cast<size_t>(effectors));
    for (int i = 0; i < effectors; ++i) {
      const std::string joint = body["effectors"][i]["joint"];
      EXPECT_EQ(rest["residuals"][i]["joint"], joint);
      EXPECT_LT(rest["residuals"][i]["positionError"].get<double>(), 1e-3 * m.ChainLength(joint, 0));
    }
    // The same numbers as the gRPC call.
    v1::SolveIkRequest request;
    request.set_skeleton("demo_walk");
    request.mutable_from_clip()->set_clip("demo_walk");
    request.mutable_from_clip()->set_time(t - 0.1);
    request.set_free_root(v1::ROOT_ROTATION);
    *request.add_effectors() = Effector("LeftWrist", wrist);
    if (effectors == 2) *request.add_effectors() = Effector("RightAnkle", ankle);
    const v1::SolveIkResponse grpc = client.SolveIk(request);
    ExpectSamePose(rest["local"], grpc.local(), "local");
    ExpectSamePose(rest["world"], grpc.world(), "world");
    EXPECT_EQ(rest["iterations"], grpc.iterations());
    for (int i = 0; i < effectors; ++i)
      EXPECT_DOUBLE_EQ(rest["residuals"][i]["positionError"].get<double>(), grpc.residuals(i).position_error());
    std::printf("  gateway %d effector(s): converged in %d iterations, residuals", effectors, grpc.iterations());
    for (const auto& res : grpc.residuals()) std::printf(" %s %.2e", res.joint().c_str(), res.position_error());
    std::printf("; REST == gRPC\n");
  }
  // Bad input: 400 naming the field; an unreachable target is a 200.
  const auto bad = http.Post("/v1/skeletons/demo_walk:solveIk",
                             R"({"effectors":[{"joint":"LeftWrist","targetPosition":[1,2]}]})", "application/json");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  EXPECT_NE(bad->body.find("effectors[0].target_position"), std::string::npos) << bad->body;
  const auto far =
      http.Post("/v1/skeletons/demo_walk:solveIk",
                R"({"effectors":[{"joint":"LeftWrist","targetPosition":[0,5000,0]}]})", "application/json");
  ASSERT_TRUE(far);
  EXPECT_EQ(far->status, 200);
  EXPECT_EQ(json::parse(far->body)["converged"], false);

  // The session over the gateway: NDJSON messages in, one SSE answer each.
  std::string ndjson =
      json({{"start",
             {{"fromClip", {{"clip", "demo_walk"}, {"time", t}}},
              {"effectors", json::array({{{"joint", "LeftWrist"}, {"targetPosition", Xyz(wrist)}}})}}}})
          .dump() +
      "\n";
  std::vector<Eigen::Vector3d> targets = {wrist};
  for (int i = 1; i <= 10; ++i) {
    targets.push_back(wrist + Eigen::Vector3d(0, 0.5 * i, 1.0 * i));
    ndjson +=
        json({{"targets", json::array({{{"effector", 0}, {"targetPosition", Xyz(targets.back())}}})}}).dump() + "\n";
  }
  const auto session = http.Post("/v1/skeletons/demo_walk:ikSession", ndjson, "application/x-ndjson");
  ASSERT_TRUE(session);
  ASSERT_EQ(session->status, 200) << session->body;
  const std::vector<SseEvent> events = ParseSse(session->body);
  ASSERT_EQ(events.size(), targets.size() + 1) << session->body.substr(0, 500);
  for (size_t i = 0; i < targets.size(); ++i) {
    const json answer = json::parse(events[i].data);
    EXPECT_EQ(answer["converged"], true) << "answer " << i;
    const json& p = answer["world"]["translations"];
    const int w = m.Joint("LeftWrist");
    const Eigen::Vector3d got(p[3 * w].get<double>(), p[3 * w + 1].get<double>(), p[3 * w + 2].get<double>());
    EXPECT_LT((got - targets[i]).norm(), 1e-3 * m.ChainLength("LeftWrist", 0)) << "answer " << i;
  }
  EXPECT_EQ(events.back().event, "status");
  EXPECT_EQ(json::parse(events.back().data)["code"], 0);
}

// A bone of zero length: Tip sits on Knuckle, which sits on Base.
constexpr char kZeroLengthBoneBvh[] = R"(HIERARCHY
ROOT Base
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Knuckle
  {
    OFFSET 0 0 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT Tip
    {
      OFFSET 0 0 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      End Site
      {
        OFFSET 1 0 0
      }
    }
  }
}
MOTION
Frames: 1
Frame Time: 0.1
0 0 0 0 0 0 0 0 0 0 0 0
)";

// One bad SolveIk request: an edit of a good one, the code it gets and a field
// its message must name.
struct IkBadCase {
  std::string what;
  std::function<void(v1::SolveIkRequest&)> edit;
  grpc::StatusCode code;
  std::string field;  // must appear in the message
};

std::vector<IkBadCase> IkBadCases() {
  using G = grpc::StatusCode;
  return {
      {"unknown joint", [](auto& r) { r.mutable_effectors(1)->set_joint("RightAnkel"); }, G::INVALID_ARGUMENT,
       "effectors[1].joint"},
      {"NaN target", [](auto& r) { r.mutable_effectors(0)->set_target_position(1, NAN); }, G::INVALID_ARGUMENT,
       "effectors[0].target_position"},
      {"2-value target", [](auto& r) { r.mutable_effectors(1)->mutable_target_position()->RemoveLast(); },
       G::INVALID_ARGUMENT, "effectors[1].target_position"},
      {"zero rotation",
       [](auto& r) {
         for (int k = 0; k < 4; ++k) r.mutable_effectors(0)->add_target_rotation(0);
       },
       G::INVALID_ARGUMENT, "effectors[0].target_rotation"},
      {"no effectors", [](auto& r) { r.clear_effectors(); }, G::INVALID_ARGUMENT, "effectors"},
      {"unknown skeleton", [](auto& r) { r.set_skeleton("nobody"); }, G::NOT_FOUND, "nobody"},
      {"zero-length chain",
       [](auto& r) {
         r.set_skeleton("stub");
         r.clear_effectors();
         *r.add_effectors() = Effector("Tip", {1, 0, 0});
       },
       G::INVALID_ARGUMENT, "zero-length chain"},
      {"contradictory Euler limit",
       [](auto& r) {
         v1::JointLimit* l = r.add_limits();
         l->set_joint("LeftElbow");
         for (double v : {-10.0, 30.0, -5.0}) l->add_min_deg(v);
         for (double v : {10.0, 20.0, 5.0}) l->add_max_deg(v);
       },
       G::INVALID_ARGUMENT, "limits[0]"},
      {"two limits on one joint",
       [](auto& r) {
         r.add_limits()->set_joint("LeftElbow");
         r.add_limits()->set_joint("LeftElbow");
       },
       G::INVALID_ARGUMENT, "limits[1].joint"},
      {"cone on an Euler limit",
       [](auto& r) {
         v1::JointLimit* l = r.add_limits();
         l->set_joint("LeftElbow");
         l->set_cone_deg(10);
       },
       G::INVALID_ARGUMENT, "limits[0].cone_deg"},
      {"negative cone",
       [](auto& r) {
         v1::JointLimit* l = r.add_limits();
         l->set_joint("LeftElbow");
         l->set_kind(v1::JointLimit::SWING_TWIST);
         l->set_cone_deg(-10);
       },
       G::INVALID_ARGUMENT, "limits[0].cone_deg"},
      {"bad Euler order", [](auto& r) { r.add_limits()->set_order("XYW"); }, G::INVALID_ARGUMENT, "limits[0].order"},
      {"start pose of the wrong size", [](auto& r) { r.mutable_start_pose()->add_rotations(1); }, G::INVALID_ARGUMENT,
       "start_pose.rotations"},
      {"start clip of another skeleton", [](auto& r) { r.mutable_from_clip()->set_clip("stub"); }, G::INVALID_ARGUMENT,
       "from_clip.clip"},
      {"negative start time",
       [](auto& r) {
         r.mutable_from_clip()->set_clip("demo_walk");
         r.mutable_from_clip()->set_time(-1);
       },
       G::INVALID_ARGUMENT, "from_clip.time"},
      {"CCD with two effectors", [](auto& r) { r.set_solver(v1::CCD); }, G::INVALID_ARGUMENT, "effectors"},
      {"unknown solver", [](auto& r) { r.set_solver(static_cast<v1::IkSolver>(42)); }, G::INVALID_ARGUMENT, "solver"},
      {"unknown root", [](auto& r) { r.set_root("Tail"); }, G::INVALID_ARGUMENT, "root"},
      {"negative tolerance", [](auto& r) { r.mutable_options()->set_position_tolerance(-1); }, G::INVALID_ARGUMENT,
       "options.position_tolerance"},
      {"over the iteration limit", [](auto& r) { r.mutable_options()->set_max_iterations(5001); },
       G::RESOURCE_EXHAUSTED, "--max-ik-iterations"},
  };
}

TEST_F(IkApi, BadInputNamesTheField) {
  ServerProcess server(data_.path(), {"--max-ik-iterations", "5000"});
  client::Client client(OptionsFor(server));
  client.Import({"stub.bvh", kZeroLengthBoneBvh});
  const std::string before = client.ListAssets().SerializeAsString();
  v1::SolveIkRequest good;
  good.set_skeleton("demo_walk");
  *good.add_effectors() = Effector("LeftWrist", {10, 100, 10});
  *good.add_effectors() = Effector("RightAnkle", {-10, 5, 0});
  ASSERT_EQ(CodeOf([&] { client.SolveIk(good); }), grpc::StatusCode::OK);

  const std::vector<IkBadCase> cases = IkBadCases();
  for (const IkBadCase& c : cases) {
    v1::SolveIkRequest r = good;
    c.edit(r);
    const grpc::Status status = StatusOf([&] { client.SolveIk(r); });
    const std::string& message = status.error_message();
    EXPECT_EQ(status.error_code(), c.code) << c.what << ": " << message;
    EXPECT_NE(message.find(c.field), std::string::npos) << c.what << ": " << message;
    std::printf("  %-32s %s\n", c.what.c_str(), message.c_str());
  }
  // At the limit is fine; still serving, nothing stored changed.
  good.mutable_options()->set_max_iterations(5000);
  EXPECT_EQ(CodeOf([&] { client.SolveIk(good); }), grpc::StatusCode::OK);
  EXPECT_TRUE(client.Healthy());
  EXPECT_EQ(client.ListAssets().SerializeAsString(), before);
}

}  // namespace
}  // namespace armature::testing
