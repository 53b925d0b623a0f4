// EvaluateMotion end to end on a real server: a motion of one layer is the
// clip, two layers blend as three.js's mixer does, root motion, the REST
// route with the documented JSON names, and bad motions answered with the
// status and a message naming the layer.
#include <cmath>
#include <string>

// Eigen (through demo_walk.h) before httplib: resolv.h, which httplib pulls
// in, defines a `_res` macro that breaks Eigen's parameter names.
#include "armature/engine/io/demo_walk.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"
#include "support/server_suite.h"

namespace armature::testing {
namespace {
using nlohmann::json;

class Motion : public ServerSuite {
 protected:
  static void SetUpTestSuite() {
    ServerSuite::SetUpTestSuite();
    client::Client client(OptionsFor(*server_));
    client.ImportFile(WriteTemp(*data_, "arm.bvh", kArmBvh), "arm");
  }
  static v1::MotionLayer* AddLayer(v1::Motion& m, const std::string& clip) {
    v1::MotionLayer* l = m.add_layers();
    l->set_clip(clip);
    return l;
  }
  static v1::EvaluateMotionResponse Evaluate(const v1::Motion& m, std::vector<double> times,
                                             v1::Space space = v1::LOCAL) {
    client::Client client(OptionsFor(*server_));
    v1::EvaluateMotionRequest r;
    *r.mutable_motion() = m;
    for (double t : times) r.add_times(t);
    r.set_space(space);
    return client.EvaluateMotion(r);
  }
  static v1::EvaluateClipResponse EvaluateClip(const std::string& clip, std::vector<double> times,
                                               v1::Space space = v1::LOCAL) {
    client::Client client(OptionsFor(*server_));
    v1::EvaluateClipRequest r;
    r.set_clip(clip);
    for (double t : times) r.add_times(t);
    r.set_space(space);
    r.set_wrap(v1::LOOP);
    return client.EvaluateClip(r);
  }
};

TEST_F(Motion, OneLayerIsTheLoopingClip) {
  v1::Motion m;
  AddLayer(m, "demo_walk");
  const std::vector<double> times = {0, 0.4, 2.5, 4.2};  // 4.2 s loops (the clip is 3 s)
  const auto got = Evaluate(m, times, v1::WORLD);
  const auto want = EvaluateClip("demo_walk", times, v1::WORLD);
  EXPECT_EQ(got.skeleton(), "demo_walk");
  ASSERT_EQ(got.poses_size(), 4);
  ASSERT_EQ(got.joints_size(), 19);
  for (int p = 0; p < 4; ++p)
    for (int i = 0; i < want.poses(p).translations_size(); ++i)
      EXPECT_NEAR(got.poses(p).translations(i), want.poses(p).translations(i), 1e-3) << p << " " << i;
}

// Two override layers of weight 1 (the same walk half a second apart, the
// second on the demo character's own skeleton, mapped by joint name): the
// mixer slerps half way, so each translation is the mean of the two.
TEST_F(Motion, TwoLayersOnSkeletonsWithTheSameJointNamesBlendHalfWay) {
  v1::Motion m;
  AddLayer(m, "demo_walk");
  AddLayer(m, "demo_character.walk")->set_time_offset(0.5);
  const auto got = Evaluate(m, {0.3});
  const auto a = EvaluateClip("demo_walk", {0.3}), b = EvaluateClip("demo_walk", {0.8});
  const auto& t = got.poses(0).translations();
  // The second layer plays demo_character.walk, a copy of the walk held
  // compressed on its own under the default bound (0.01 cm): the mean may
  // differ from demo_walk's by up to that bound, on top of float rounding.
  constexpr double kDefaultBoundCm = 0.01;
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(t[i], 0.5 * (a.poses(0).translations(i) + b.poses(0).translations(i)), 1e-3 + kDefaultBoundCm) << i;
  EXPECT_GT(std::abs(a.poses(0).translations(2) - b.poses(0).translations(2)), 10.0);  // the root moved apart
}

TEST_F(Motion, InPlaceAndExtractKeepTheRootOverItsStart) {
  v1::Motion m;
  AddLayer(m, "demo_walk");
  m.set_root_motion(v1::Motion::IN_PLACE);
  const auto in_place = Evaluate(m, {0, 1.1, 2.2});
  for (int p = 0; p < 3; ++p) {
    EXPECT_NEAR(in_place.poses(p).translations(0), in_place.poses(0).translations(0), 1e-4);
    EXPECT_NEAR(in_place.poses(p).translations(2), in_place.poses(0).translations(2), 1e-4);
  }
  m.set_root_motion(v1::Motion::EXTRACT);
  const auto extracted = Evaluate(m, {0, 1.1, 4.0});
  ASSERT_EQ(extracted.root_motion_size(), 3);
  EXPECT_NEAR(extracted.root_motion(1).translations(2), kDemoWalkSpeed * 1.1, 0.05);
  EXPECT_NEAR(extracted.root_motion(2).translations(2), kDemoWalkSpeed * 4.0, 0.05);  // on, past the loop point
  EXPECT_EQ(extracted.root_motion(2).rotations_size(), 4);
  EXPECT_EQ(in_place.root_motion_size(), 0);
}

TEST_F(Motion, BadMotionsNameTheLayer) {
  auto expect = [](const v1::Motion& m, grpc::StatusCode code, std::vector<std::string> parts) {
    const grpc::Status st = StatusOf([&] { Evaluate(m, {0.5}); });
    EXPECT_EQ(st.error_code(), code) << st.error_message();
    for (const auto& p : parts) EXPECT_NE(st.error_message().find(p), std::string::npos) << st.error_message();
  };
  expect(v1::Motion{}, grpc::StatusCode::INVALID_ARGUMENT, {"motion.layers", "empty"});
  v1::Motion unknown;
  AddLayer(unknown, "demo_walk");
  AddLayer(unknown, "no_such_clip");
  expect(unknown, grpc::StatusCode::NOT_FOUND, {"layers[1]", "no_such_clip"});
  v1::Motion mismatch;
  AddLayer(mismatch, "demo_walk");
  AddLayer(mismatch, "arm");
  expect(mismatch, grpc::StatusCode::INVALID_ARGUMENT,
         {"layers[1] (clip 'arm')", "lacks 19 of the 19 joints", "'Hips'"});
  v1::Motion heavy;
  AddLayer(heavy, "demo_walk");
  AddLayer(heavy, "demo_walk")->set_weight(1.5);
  expect(heavy, grpc::StatusCode::INVALID_ARGUMENT, {"layers[1] (clip 'demo_walk')", "weight", "[0, 1]"});
  heavy.mutable_layers(1)->set_weight(-0.5);
  expect(heavy, grpc::StatusCode::INVALID_ARGUMENT, {"layers[1]", "weight"});
  v1::Motion masked;
  AddLayer(masked, "demo_walk")->add_mask("Tail");
  expect(masked, grpc::StatusCode::NOT_FOUND, {"layers[0]", "mask joint 'Tail'"});
  v1::Motion bad_enum;
  AddLayer(bad_enum, "demo_walk")->set_mode(static_cast<v1::MotionLayer::Mode>(9));
  expect(bad_enum, grpc::StatusCode::INVALID_ARGUMENT, {"layers[0]", "mode", "9"});
  // The server still answers.
  v1::Motion fine;
  AddLayer(fine, "demo_walk");
  EXPECT_EQ(Evaluate(fine, {0.5}).poses_size(), 1);
}

// The documented JSON names over REST; unset weight and speed mean 1.
TEST_F(Motion, RestRouteTakesTheDocumentedJsonNames) {
  httplib::Client http("127.0.0.1", server_->http_port());
  http.set_read_timeout(60);
  const json body = {{"motion",
                      {{"layers",
                        {{{"clip", "demo_walk"}, {"mode", "OVERRIDE"}, {"wrap", "LOOP"}, {"timeOffset", 0}},
                         {{"clip", "demo_walk"},
                          {"weight", 0.5},
                          {"speed", 2},
                          {"mode", "ADDITIVE"},
                          {"referenceTime", 0.2},
                          {"mask", {"LeftShoulder"}},
                          {"wrap", "CLAMP"}}}},
                       {"sync", "PHASE"},
                       {"rootMotion", "IN_PLACE"}}},
                     {"times", {0.5}},
                     {"space", "WORLD"}};
  const auto r = http.Post("/v1/motions:evaluate", body.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json j = json::parse(r->body);
  EXPECT_EQ(j["skeleton"], "demo_walk");
  EXPECT_EQ(j["poses"].size(), 1u);
  EXPECT_EQ(j["poses"][0]["translations"].size(), 3u * 19);

  json bad = body;
  bad["motion"]["layers"][1]["weight"] = 2;
  const auto e = http.Post("/v1/motions:evaluate", bad.dump(), "application/json");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->status, 400) << e->body;
  EXPECT_NE(e->body.find("layers[1]"), std::string::npos) << e->body;
}

}  // namespace
}  // namespace armature::testing
