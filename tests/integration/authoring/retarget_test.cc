// RetargetClip over the API on a real server (issue 14's done-when): CMU
// 01_01 onto RobotExpressive and onto the demo character; every limb bone
// and the spine to the head point within 10° of the source's after one
// global yaw; the hips at the leg-length ratio; with feet, a planted source
// foot keeps the target's foot within 1 % of its leg length. The new clip
// survives a restart, lists, evaluates, skins RobotExpressive's meshes, exports
// with them, and outlives its source. Bad input is INVALID_ARGUMENT naming it.
// Skipped when ../shared/data is absent.
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <string>
#include <vector>

// The engine first: a system header included later defines a macro Eigen's headers trip on.
#include "armature/engine/io/gltf/gltf.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"
#include "support/server_suite.h"

namespace armature::testing {
namespace {

struct V3 {
  double x = 0, y = 0, z = 0;
  V3 operator-(const V3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  V3 operator+(const V3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  V3 operator*(double s) const { return {x * s, y * s, z * s}; }
  double Norm() const { return std::sqrt(x * x + y * y + z * z); }
};

using Frame = std::map<std::string, V3>;  // joint name → world position

// World joint positions of `clip` at `times`, by joint name (batches of 100 times).
std::vector<Frame> WorldPositions(client::Client& client, const std::string& clip, const std::vector<double>& times) {
  const v1::Skeleton skeleton = client.GetSkeleton(client.GetClip(clip).skeleton());
  std::vector<Frame> out;
  for (size_t begin = 0; begin < times.size(); begin += 100) {
    v1::EvaluateClipRequest r;
    r.set_clip(clip);
    r.set_space(v1::WORLD);
    for (size_t i = begin; i < std::min(times.size(), begin + 100); ++i) r.add_times(times[i]);
    const auto response = client.EvaluateClip(r);
    for (const v1::Pose& pose : response.poses()) {
      Frame f;
      for (int k = 0; k < response.joints_size(); ++k)
        f[skeleton.joints(response.joints(k)).name()] = {pose.translations(3 * k), pose.translations(3 * k + 1),
                                                         pose.translations(3 * k + 2)};
      out.push_back(std::move(f));
    }
  }
  return out;
}

struct Bone {
  std::string source_from, source_to, target_from, target_to;
};

// The tested bones, named by hand for each target (an independent reading of the map).
// CMU's Neck sits on Spine1 (a zero offset): the chest has no bone of its own to compare.
std::vector<Bone> RobotBones() {
  std::vector<Bone> b = {{"Hips", "Spine", "Hips", "Abdomen"},
                         {"Spine", "Spine1", "Abdomen", "Torso_1"},
                         {"Neck", "Head", "Neck", "Head"}};
  for (const auto& [s, t] : {std::pair<std::string, std::string>{"Left", "L"}, {"Right", "R"}}) {
    b.push_back({s + "Arm", s + "ForeArm", "UpperArm" + t, "LowerArm" + t});
    b.push_back({s + "ForeArm", s + "Hand", "LowerArm" + t, "Palm2" + t});
    b.push_back({s + "UpLeg", s + "Leg", "UpperLeg" + t, "LowerLeg" + t});
    b.push_back({s + "Leg", s + "Foot", "LowerLeg" + t, "Foot" + t});
  }
  return b;
}

std::vector<Bone> DemoBones() {
  std::vector<Bone> b = {
      {"Hips", "Spine", "Hips", "Spine"}, {"Spine", "Spine1", "Spine", "Chest"}, {"Neck", "Head", "Neck", "Head"}};
  for (const std::string s : {"Left", "Right"}) {
    b.push_back({s + "Arm", s + "ForeArm", s + "Shoulder", s + "Elbow"});
    b.push_back({s + "ForeArm", s + "Hand", s + "Elbow", s + "Wrist"});
    b.push_back({s + "UpLeg", s + "Leg", s + "Hip", s + "Knee"});
    b.push_back({s + "Leg", s + "Foot", s + "Knee", s + "Ankle"});
  }
  return b;
}

struct Legs {
  std::string left_thigh, right_thigh, left_knee, right_knee, left_ankle, right_ankle;
};
const Legs kCmuLegs = {"LeftUpLeg", "RightUpLeg", "LeftLeg", "RightLeg", "LeftFoot", "RightFoot"};
const Legs kRobotLegs = {"UpperLegL", "UpperLegR", "LowerLegL", "LowerLegR", "FootL", "FootR"};
const Legs kDemoLegs = {"LeftHip", "RightHip", "LeftKnee", "RightKnee", "LeftAnkle", "RightAnkle"};

// Thigh + shin, the mean of both legs (CMU's differ by 2 %).
double LegLength(const Frame& f, const Legs& l) {
  return 0.5 * ((f.at(l.left_knee) - f.at(l.left_thigh)).Norm() + (f.at(l.left_ankle) - f.at(l.left_knee)).Norm() +
                (f.at(l.right_knee) - f.at(l.right_thigh)).Norm() + (f.at(l.right_ankle) - f.at(l.right_knee)).Norm());
}
double HipHeight(const Frame& f, const Legs& l) { return 0.5 * (f.at(l.left_thigh).y + f.at(l.right_thigh).y); }

class Retarget : public CmuAndRobotSuite {
 protected:
  static v1::RetargetClipResponse Run(const std::string& skeleton, const std::string& name, bool feet = false) {
    client::Client client(OptionsFor(*server_));
    v1::RetargetClipRequest r;
    r.set_clip("cmu");
    r.set_skeleton(skeleton);
    r.set_name(name);
    r.set_feet(feet);
    r.set_replace(true);
    return client.RetargetClip(r);
  }
};

// The largest angle between a target bone and the source's, after the one yaw
// that best turns every source bone onto the target's (least squares on the
// horizontal components), at 10 times.
double MaxBoneAngle(client::Client& client, const std::string& clip, const std::vector<Bone>& bones,
                    double* yaw_degrees) {
  const double duration = client.GetClip("cmu").duration();
  std::vector<double> times;
  for (int i = 0; i < 10; ++i) times.push_back(duration * (i + 0.5) / 10);
  const auto source = WorldPositions(client, "cmu", times), target = WorldPositions(client, clip, times);
  double sin_sum = 0, cos_sum = 0;
  for (size_t i = 0; i < times.size(); ++i)
    for (const Bone& b : bones) {
      const V3 s = source[i].at(b.source_to) - source[i].at(b.source_from);
      const V3 t = target[i].at(b.target_to) - target[i].at(b.target_from);
      // The yaw about +Y taking s to t: sin from (s × t).y, cos from the horizontal dot.
      sin_sum += (s.z * t.x - s.x * t.z) / (s.Norm() * t.Norm());
      cos_sum += (s.x * t.x + s.z * t.z) / (s.Norm() * t.Norm());
    }
  const double yaw = std::atan2(sin_sum, cos_sum);
  *yaw_degrees = yaw * 180 / std::numbers::pi;
  double worst = 0;
  for (size_t i = 0; i < times.size(); ++i)
    for (const Bone& b : bones) {
      V3 s = source[i].at(b.source_to) - source[i].at(b.source_from);
      s = {std::cos(yaw) * s.x + std::sin(yaw) * s.z, s.y, -std::sin(yaw) * s.x + std::cos(yaw) * s.z};
      const V3 t = target[i].at(b.target_to) - target[i].at(b.target_from);
      const double cos_angle = (s.x * t.x + s.y * t.y + s.z * t.z) / (s.Norm() * t.Norm());
      const double angle = std::acos(std::clamp(cos_angle, -1.0, 1.0)) * 180 / std::numbers::pi;
      EXPECT_LT(angle, 10.0) << clip << " " << b.target_from << "→" << b.target_to << " at t=" << times[i];
      worst = std::max(worst, angle);
    }
  return worst;
}

// The hip-height ratio's largest departure from the leg-length ratio, at 10 times.
double MaxHipRatioError(client::Client& client, const std::string& clip, const Legs& legs) {
  const double duration = client.GetClip("cmu").duration();
  std::vector<double> times;
  for (int i = 0; i < 10; ++i) times.push_back(duration * (i + 0.5) / 10);
  const auto source = WorldPositions(client, "cmu", times), target = WorldPositions(client, clip, times);
  const double leg_ratio = LegLength(target[0], legs) / LegLength(source[0], kCmuLegs);
  double worst = 0;
  for (size_t i = 0; i < times.size(); ++i)
    worst = std::max(worst, std::abs(HipHeight(target[i], legs) / HipHeight(source[i], kCmuLegs) / leg_ratio - 1));
  return worst;
}

// The farthest a target foot strays, over stretches (≥ 4 samples at 30 Hz)
// where the source's ankle is within 5 % of its leg length of its lowest and
// slower than 15 % of its leg length per second, as a fraction of the target's leg length.
double MaxPlantedDrift(client::Client& client, const std::string& clip, const Legs& legs, int* stretches) {
  const double duration = client.GetClip("cmu").duration();
  std::vector<double> times;
  for (double t = 0; t <= duration; t += 1.0 / 30) times.push_back(t);
  const auto source = WorldPositions(client, "cmu", times), target = WorldPositions(client, clip, times);
  const double ls = LegLength(source[0], kCmuLegs), lt = LegLength(target[0], legs);
  double worst = 0;
  *stretches = 0;
  for (int side = 0; side < 2; ++side) {
    const std::string sa = side == 0 ? kCmuLegs.left_ankle : kCmuLegs.right_ankle;
    const std::string ta = side == 0 ? legs.left_ankle : legs.right_ankle;
    double ground = 1e30;
    for (const Frame& f : source) ground = std::min(ground, f.at(sa).y);
    std::vector<bool> planted(times.size());
    for (size_t i = 1; i + 1 < times.size(); ++i)
      planted[i] = source[i].at(sa).y - ground < 0.05 * ls &&
                   (source[i + 1].at(sa) - source[i - 1].at(sa)).Norm() / (times[i + 1] - times[i - 1]) < 0.15 * ls;
    for (size_t i = 0; i < times.size();) {
      size_t end = i;
      while (end < times.size() && planted[end]) ++end;
      if (end - i >= 4) {
        ++*stretches;
        for (size_t a = i; a < end; ++a)
          for (size_t b = a + 1; b < end; ++b)
            worst = std::max(worst, (target[a].at(ta) - target[b].at(ta)).Norm() / lt);
      }
      i = std::max(end, i + 1);
    }
  }
  return worst;
}

TEST_F(Retarget, CmuOntoRobotExpressiveAndTheDemoCharacterKeepsBonesHipsAndPlantedFeet) {
  client::Client client(OptionsFor(*server_));
  struct Case {
    std::string skeleton, name;
    std::vector<Bone> bones;
    Legs legs;
  };
  const Case cases[] = {{"robot", "cmu_on_robot", RobotBones(), kRobotLegs},
                        {"demo_character", "cmu_on_demo", DemoBones(), kDemoLegs}};
  for (const Case& c : cases) {
    const auto r = Run(c.skeleton, c.name);
    EXPECT_EQ(r.clip().name(), c.name);  // the name given is the name to call
    EXPECT_EQ(r.clip().skeleton(), c.skeleton);
    EXPECT_EQ(r.asset().name(), c.name);
    double yaw = 0;
    const double angle = MaxBoneAngle(client, r.clip().name(), c.bones, &yaw);
    const double hips = MaxHipRatioError(client, r.clip().name(), c.legs);
    EXPECT_LT(hips, 0.05) << c.skeleton;
    const auto with_feet = Run(c.skeleton, c.name + "_feet", true);
    int stretches = 0;
    const double drift = MaxPlantedDrift(client, with_feet.clip().name(), c.legs, &stretches);
    EXPECT_GT(stretches, 0) << c.skeleton;
    EXPECT_LT(drift, 0.01) << c.skeleton;
    const double hips_feet = MaxHipRatioError(client, with_feet.clip().name(), c.legs);
    EXPECT_LT(hips_feet, 0.05) << c.skeleton << " with feet";
    std::printf(
        "CMU 01_01 onto %s: max bone angle %.4f° (yaw %.1f°), hip ratio off the leg ratio by %.4f %% "
        "(%.4f %% with feet), planted foot drift %.4f %% of the leg over %d stretches\n",
        c.skeleton.c_str(), angle, yaw, 100 * hips, 100 * hips_feet, 100 * drift, stretches);
  }
}

TEST_F(Retarget, TheMapAnswerListsPairsAndUnmappedJointsAndExplicitPairsOverride) {
  const auto r = Run("demo_character", "cmu_on_demo_map");
  std::map<std::string, std::string> pairs;
  for (const auto& p : r.mapping()) pairs[p.target()] = p.source();
  EXPECT_EQ(pairs["LeftShoulder"], "LeftArm");
  EXPECT_EQ(pairs["LeftHip"], "LeftUpLeg");
  EXPECT_EQ(r.mapping_size(), 19);  // every demo joint
  EXPECT_EQ(r.unmapped().target_size(), 0);
  EXPECT_EQ(r.mapping_size() + r.unmapped().source_size(), 31);  // every CMU joint once
  client::Client client(OptionsFor(*server_));
  v1::RetargetClipRequest req;
  req.set_clip("cmu");
  req.set_skeleton("demo_character");
  req.set_name("cmu_on_demo_explicit");
  auto* pair = req.add_map();
  pair->set_source("Neck1");
  pair->set_target("Neck");
  const auto explicit_map = client.RetargetClip(req);
  for (const auto& p : explicit_map.mapping())
    if (p.target() == "Neck") EXPECT_EQ(p.source(), "Neck1");
}

TEST_F(Retarget, TheNewClipPersistsSkinsExportsWithMeshesAndOutlivesItsSource) {
  {
    client::Client client(OptionsFor(*server_));

    client.ImportFile(SharedData("bvh/cmu_01_01.bvh"), "cmu_copy");

    v1::RetargetClipRequest r;

    r.set_clip("cmu_copy");

    r.set_skeleton("robot");

    const auto made = client.RetargetClip(r);

    EXPECT_EQ(made.asset().name(), "cmu_copy_on_robot");  // the default name
  }
  const std::string clip = "cmu_copy_on_robot";
  auto sample = [&](client::Client& client) {
    v1::EvaluateClipRequest e;

    e.set_clip(clip);
    e.add_times(1.25);
    e.set_space(v1::WORLD);
    return client.EvaluateClip(e);
  };
  v1::EvaluateClipResponse before;
  {
    client::Client client(OptionsFor(*server_));

    before = sample(client);
  }
  ASSERT_EQ(before.poses_size(), 1);
  // A restart on the same data dir.
  delete server_;
  server_ = new ServerProcess(data_->path());
  client::Client client(OptionsFor(*server_));
  bool listed = false;
  const auto clips = client.ListClips();  // held: a temporary's member would die before the loop
  for (const auto& c : clips.clips()) listed |= c.name() == clip;
  EXPECT_TRUE(listed);
  const auto after = sample(client);
  ASSERT_EQ(after.poses_size(), 1);
  ASSERT_EQ(after.poses(0).translations_size(), before.poses(0).translations_size());
  for (int k = 0; k < after.poses(0).translations_size(); ++k)
    EXPECT_NEAR(after.poses(0).translations(k), before.poses(0).translations(k), 1e-5);

  // The source deleted: the new clip still evaluates, skins and exports.
  client.DeleteAsset("cmu_copy");
  const auto still = sample(client);
  ASSERT_EQ(still.poses_size(), 1);
  EXPECT_EQ(still.poses(0).translations(3), before.poses(0).translations(3));
  int skinned = 0;
  const auto meshes = client.ListMeshes();
  for (const auto& m : meshes.meshes()) {
    if (m.asset() != "robot" || m.skeleton().empty()) continue;

    v1::SkinMeshRequest s;

    s.set_mesh(m.name());

    s.set_clip(clip);

    s.set_time(1.25);

    const auto out = client.SkinMesh(s);

    EXPECT_EQ(out.vertex_count(), m.vertex_count());

    ++skinned;
  }
  EXPECT_GT(skinned, 0);
  const auto glb = client.ExportClip(clip, "glb", true);
  auto contents = ParseGltf(glb.data(), true, "back");
  ASSERT_TRUE(contents.ok()) << contents.status().message();
  EXPECT_EQ(static_cast<int>(contents->meshes.size()), skinned);
  EXPECT_EQ(contents->clips.size(), 1u);
}

// The retargeted clip is the target's own: listed with the robot's clips
// (joint for joint its skeleton), first layer of a motion skinned on a robot
// mesh (it was "animates skeleton 'rt0', not the mesh's skeleton 'robot'")
// and blended with the robot's Idle, exactly as the robot's own clips are.
TEST_F(Retarget, TheClipBelongsToTheTargetAndBlendsAndSkinsWithItsOwnClips) {
  client::Client client(OptionsFor(*server_));
  const auto made = Run("robot", "rt0");
  EXPECT_EQ(made.clip().name(), "rt0");
  EXPECT_EQ(made.clip().skeleton(), "robot");
  EXPECT_EQ(made.asset().skeletons_size(), 0);  // no copy of the robot's skeleton beside it
  const v1::Skeleton robot = client.GetSkeleton("robot");
  const v1::ClipInfo info = client.GetClip("rt0");
  ASSERT_EQ(info.joints_size(), robot.joints_size());
  for (int j = 0; j < robot.joints_size(); ++j) EXPECT_EQ(info.joints(j), robot.joints(j).name());
  int robot_clips = 0;
  bool listed = false;
  const auto clips = client.ListClips();
  for (const auto& c : clips.clips())
    if (c.skeleton() == "robot") ++robot_clips, listed |= c.name() == "rt0";
  EXPECT_TRUE(listed);
  EXPECT_GE(robot_clips, 15);  // the robot's 14, rt0 and the suite's other clips made for it

  std::string mesh;
  uint32_t most = 0;
  const auto meshes = client.ListMeshes();
  for (const auto& m : meshes.meshes())
    if (m.skeleton() == "robot" && static_cast<uint32_t>(m.vertex_count()) > most)
      mesh = m.name(), most = m.vertex_count();
  ASSERT_FALSE(mesh.empty());
  auto skin = [&](double idle_weight) {
    v1::SkinMeshRequest s;
    s.set_mesh(mesh);
    s.set_time(1.25);
    v1::MotionLayer* rt0 = s.mutable_motion()->add_layers();
    rt0->set_clip("rt0");
    rt0->set_weight(1.0);
    v1::MotionLayer* idle = s.mutable_motion()->add_layers();
    idle->set_clip("robot.Idle");
    idle->set_weight(idle_weight);
    return client.SkinMesh(s);
  };
  v1::SkinMeshRequest by_clip;
  by_clip.set_mesh(mesh);
  by_clip.set_clip("rt0");
  by_clip.set_time(1.25);
  const auto alone = client.SkinMesh(by_clip);
  const auto layered = skin(0.0), blended = skin(0.5);
  ASSERT_EQ(layered.positions_size(), alone.positions_size());
  ASSERT_EQ(blended.positions_size(), alone.positions_size());
  double same = 0, moved = 0;
  for (int k = 0; k < alone.positions_size(); ++k) {
    same = std::max<double>(same, std::abs(layered.positions(k) - alone.positions(k)));
    moved = std::max<double>(moved, std::abs(blended.positions(k) - alone.positions(k)));
  }
  EXPECT_LT(same, 1e-5);   // at weight 0 the Idle layer changes nothing
  EXPECT_GT(moved, 1e-3);  // at 0.5 it does
  std::printf("rt0 on %s (%u vertices): weight-0 Idle layer off by %.2g, weight 0.5 moves vertices up to %.3g\n",
              mesh.c_str(), most, same, moved);
}

TEST_F(Retarget, BadInputIsInvalidArgumentNamingIt) {
  client::Client client(OptionsFor(*server_));
  auto call = [&](const std::string& skeleton, const std::vector<std::pair<std::string, std::string>>& map,
                  bool feet = false) {
    v1::RetargetClipRequest r;
    r.set_clip("cmu");
    r.set_skeleton(skeleton);
    r.set_name("bad");
    r.set_feet(feet);
    for (const auto& [s, t] : map) {
      auto* p = r.add_map();
      p->set_source(s);
      p->set_target(t);
    }
    return StatusOf([&] { client.RetargetClip(r); });
  };
  const auto unknown = call("robot", {{"LeftArm", "UpperArmLL"}});
  EXPECT_EQ(unknown.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(unknown.error_message().find("map[0].target: unknown joint 'UpperArmLL'; did you mean 'UpperArmL'?"),
            std::string::npos)
      << unknown.error_message();
  const auto unknown_source = call("robot", {{"LeftArmm", "UpperArmL"}});
  EXPECT_EQ(unknown_source.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(unknown_source.error_message().find("map[0].source: unknown joint 'LeftArmm'"), std::string::npos)
      << unknown_source.error_message();
  const auto onto_two = call("robot", {{"LeftArm", "UpperArmL"}, {"RightArm", "UpperArmL"}});
  EXPECT_EQ(onto_two.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(
      onto_two.error_message().find("map[1]: target joint 'UpperArmL' is already mapped from 'LeftArm' by map[0]"),
      std::string::npos)
      << onto_two.error_message();
  const auto from_one = call("robot", {{"LeftArm", "UpperArmL"}, {"LeftArm", "UpperArmR"}});
  EXPECT_EQ(from_one.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(from_one.error_message().find("map[1]: source joint 'LeftArm' already drives 'UpperArmL'"),
            std::string::npos)
      << from_one.error_message();
  // A target without legs: an arm of two joints, mapped explicitly.
  TempDir dir;
  client.ImportFile(WriteTemp(dir, "arm.bvh", kArmBvh), "arm");
  const auto no_legs = call("arm", {{"LeftArm", "Base"}, {"LeftForeArm", "Tip"}}, true);
  EXPECT_EQ(no_legs.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(no_legs.error_message().find("feet: the target's left leg has no hip–knee–ankle chain"), std::string::npos)
      << no_legs.error_message();
  EXPECT_EQ(call("arm", {}).error_code(), grpc::StatusCode::INVALID_ARGUMENT);  // nothing maps by name
  EXPECT_EQ(call("no_such_skeleton", {}).error_code(), grpc::StatusCode::NOT_FOUND);
  // Nothing was stored.
  EXPECT_EQ(StatusOf([&] { client.GetAsset("bad"); }).error_code(), grpc::StatusCode::NOT_FOUND);
}

TEST_F(Retarget, RestPostsToClipRetarget) {
  httplib::Client http("127.0.0.1", server_->http_port());
  const auto ok =
      http.Post("/v1/clips/cmu:retarget",
                R"({"skeleton":"demo_character","name":"rest_retarget","map":[{"source":"Neck1","target":"Neck"}]})",
                "application/json");
  ASSERT_TRUE(ok);
  ASSERT_EQ(ok->status, 200) << ok->body;
  const auto body = nlohmann::json::parse(ok->body);
  EXPECT_EQ(body["clip"]["name"], "rest_retarget");
  EXPECT_EQ(body["asset"]["name"], "rest_retarget");
  EXPECT_EQ(body["mapping"].size(), 19u);
  const auto bad = http.Post("/v1/clips/cmu:retarget",
                             R"({"skeleton":"robot","map":[{"source":"Nope","target":"Head"}]})", "application/json");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400) << bad->body;
  EXPECT_NE(bad->body.find("map[0].source: unknown joint 'Nope'"), std::string::npos) << bad->body;
}

TEST_F(Retarget, TheCliPrintsTheClipTheMappingAndTheUnmappedJoints) {
  const CommandResult r = RunCli(server_->target(), {"retarget", "cmu", "--to", "demo_character", "--name",
                                                     "cli_retarget", "--map", "Neck1=Neck", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["clip"]["name"], "cli_retarget");
  EXPECT_EQ(j["clip"]["skeleton"], "demo_character");
  ASSERT_TRUE(j["mapping"].is_array());
  bool neck = false;
  for (const auto& p : j["mapping"]) neck |= p["source"] == "Neck1" && p["target"] == "Neck";
  EXPECT_TRUE(neck);
  EXPECT_TRUE(j["unmapped"]["source"].is_array());
  EXPECT_TRUE(j["unmapped"]["target"].is_array());
  const CommandResult bad = RunCli(server_->target(), {"retarget", "cmu", "--to", "robot", "--map", "LeftArm"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("expected SOURCE=TARGET"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace armature::testing
