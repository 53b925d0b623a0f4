// SkinMesh and StreamSkinnedMesh with a motion instead of a clip, on the demo
// character of a real server: a one-layer motion skins as its clip does, a
// streamed frame is SkinMesh at the frame's time, and clip, motion and pose
// are exclusive with errors naming the fields.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"
#include "support/server_suite.h"

namespace armature::testing {
namespace {

constexpr char kMesh[] = "demo_character.body";

class MotionSkin : public ServerSuite {
 protected:
  static v1::SkinMeshResponse Skin(v1::SkinMeshRequest r) {
    r.set_mesh(kMesh);
    return client::Client(OptionsFor(*server_)).SkinMesh(r);
  }
  static void ExpectSame(const v1::SkinMeshResponse& a, const v1::SkinMeshResponse& b, float tolerance) {
    ASSERT_EQ(a.positions_size(), b.positions_size());
    ASSERT_EQ(a.normals_size(), b.normals_size());
    for (int i = 0; i < a.positions_size(); ++i) ASSERT_NEAR(a.positions(i), b.positions(i), tolerance) << i;
    for (int i = 0; i < a.normals_size(); ++i) ASSERT_NEAR(a.normals(i), b.normals(i), tolerance) << i;
  }
};

TEST_F(MotionSkin, OneLayerMotionSkinsAsItsClip) {
  for (double t : {0.0, 0.7, 2.3}) {
    v1::SkinMeshRequest by_clip, by_motion;
    by_clip.set_clip("demo_character.walk");
    by_clip.set_time(t);
    by_clip.set_wrap(v1::LOOP);
    by_motion.mutable_motion()->add_layers()->set_clip("demo_character.walk");
    by_motion.set_time(t);
    const auto a = Skin(by_clip), b = Skin(by_motion);
    ASSERT_GT(a.vertex_count(), 100);
    EXPECT_EQ(b.mesh(), kMesh);
    EXPECT_EQ(b.vertex_count(), a.vertex_count());
    ExpectSame(a, b, 1e-3f);  // centimetres
  }
  // A different time poses differently (the comparison can fail).
  v1::SkinMeshRequest early, late;
  early.mutable_motion()->add_layers()->set_clip("demo_character.walk");
  late = early;
  late.set_time(0.5);
  const auto e = Skin(early), l = Skin(late);
  double moved = 0;
  for (int i = 0; i < e.positions_size(); ++i)
    moved = std::max(moved, double(std::abs(e.positions(i) - l.positions(i))));
  EXPECT_GT(moved, 10.0);
}

// A two-layer motion streamed on the mesh: each frame is SkinMesh with the
// motion at the frame's (unwrapped) time.
TEST_F(MotionSkin, StreamedFrameIsSkinMeshAtItsTime) {
  v1::StreamSkinnedMeshRequest r;
  r.set_mesh(kMesh);
  v1::Motion& m = *r.mutable_motion();
  m.add_layers()->set_clip("demo_character.walk");
  v1::MotionLayer* second = m.add_layers();
  second->set_clip("demo_walk");
  second->set_time_offset(0.4);
  second->set_weight(0.3);
  m.set_root_motion(v1::Motion::ACCUMULATE);
  r.set_fps(60);
  r.set_speed(10);
  r.set_start_time(2.6);
  r.set_duration(0.1);
  r.set_loop(true);
  std::vector<v1::SkinnedMeshFrame> frames;
  client::Client(OptionsFor(*server_)).StreamSkinnedMesh(r, [&](const v1::SkinnedMeshFrame& f) {
    frames.push_back(f);
    return true;
  });
  ASSERT_GE(frames.size(), 4u);
  EXPECT_GT(frames.back().time(), 3.0);  // past the loop point, not wrapped
  for (const auto& f : {frames.front(), frames.back()}) {
    v1::SkinMeshRequest one;
    *one.mutable_motion() = m;
    one.set_time(f.time());
    const auto want = Skin(one);
    v1::SkinMeshResponse got;
    *got.mutable_positions() = f.positions();
    *got.mutable_normals() = f.normals();
    ExpectSame(got, want, 0);
    EXPECT_FALSE(f.has_root_delta());
  }
}

TEST_F(MotionSkin, SourcesAreExclusiveAndErrorsNameTheField) {
  auto message = [](const v1::SkinMeshRequest& r, grpc::StatusCode code) {
    const grpc::Status st = StatusOf([&] { Skin(r); });
    EXPECT_EQ(st.error_code(), code) << st.error_message();
    return st.error_message();
  };
  v1::SkinMeshRequest both;
  both.set_clip("demo_character.walk");
  both.mutable_motion()->add_layers()->set_clip("demo_character.walk");
  EXPECT_NE(message(both, grpc::StatusCode::INVALID_ARGUMENT).find("clip and motion"), std::string::npos);
  v1::SkinMeshRequest with_pose;
  with_pose.mutable_motion()->add_layers()->set_clip("demo_character.walk");
  with_pose.mutable_pose()->add_rotations(1);
  EXPECT_NE(message(with_pose, grpc::StatusCode::INVALID_ARGUMENT).find("motion and pose"), std::string::npos);
  // The first layer must animate the mesh's skeleton; other layers map by joint name.
  client::Client(OptionsFor(*server_)).ImportFile(WriteTemp(*data_, "arm.bvh", kArmBvh), "arm");
  v1::SkinMeshRequest other;
  other.mutable_motion()->add_layers()->set_clip("arm");
  const std::string m = message(other, grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(m.find("motion.layers[0]"), std::string::npos) << m;
  EXPECT_NE(m.find("demo_character"), std::string::npos) << m;
  v1::SkinMeshRequest bad_weight;
  bad_weight.mutable_motion()->add_layers()->set_clip("demo_character.walk");
  bad_weight.mutable_motion()->mutable_layers(0)->set_weight(2);
  EXPECT_NE(message(bad_weight, grpc::StatusCode::INVALID_ARGUMENT).find("motion.layers[0]"), std::string::npos);
  v1::StreamSkinnedMeshRequest stream;
  stream.set_mesh(kMesh);
  stream.set_clip("demo_character.walk");
  stream.mutable_motion()->add_layers()->set_clip("demo_character.walk");
  const grpc::Status st = StatusOf([&] {
    client::Client(OptionsFor(*server_)).StreamSkinnedMesh(stream, [](const v1::SkinnedMeshFrame&) { return true; });
  });
  EXPECT_EQ(st.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(st.error_message().find("clip and motion"), std::string::npos) << st.error_message();
}

}  // namespace
}  // namespace armature::testing
