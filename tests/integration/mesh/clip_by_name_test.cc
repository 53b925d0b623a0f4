// A clip plays on any skeleton with the same joint names: the demo walk's
// BVH (skeleton demo_walk) skins the demo character's glTF mesh (skeleton
// demo_character), unary and streamed, and equals skinning by the pose
// EvaluateClip gives for demo_walk, passed as a pose of demo_character.
// A clip whose skeleton lacks joints is refused, naming them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

// The largest coordinate difference between two vertex arrays.
double MaxDifference(const google::protobuf::RepeatedField<float>& a, const google::protobuf::RepeatedField<float>& b) {
  EXPECT_EQ(a.size(), b.size());
  double worst = 0;
  for (int i = 0; i < std::min(a.size(), b.size()); ++i) worst = std::max(worst, std::abs(double(a[i]) - b[i]));
  return worst;
}

class ClipByName : public ::testing::Test {
 protected:
  TempDir data_;
  TempDir files_;  // the test's own files, apart from the server's data
};

TEST_F(ClipByName, DemoWalkSkinsTheDemoCharacter) {
  ServerProcess server(data_.path());
  client::Client client(OptionsFor(server));
  for (const double t : {0.0, 0.5, 1.3, 2.9}) {
    v1::SkinMeshRequest by_clip;
    by_clip.set_mesh("demo_character.body");
    by_clip.set_clip("demo_walk");
    by_clip.set_time(t);
    const v1::SkinMeshResponse actual = client.SkinMesh(by_clip);
    ASSERT_EQ(actual.vertex_count(), 7506);

    // The expectation: demo_walk's local pose at t (every joint's rotation
    // and translation), given to SkinMesh as a pose of demo_character.
    v1::EvaluateClipRequest evaluate;
    evaluate.set_clip("demo_walk");
    evaluate.add_times(t);
    evaluate.set_space(v1::LOCAL);
    const v1::Pose local = client.EvaluateClip(evaluate).poses(0);
    v1::SkinMeshRequest by_pose;
    by_pose.set_mesh("demo_character.body");
    *by_pose.mutable_pose()->mutable_rotations() = local.rotations();
    *by_pose.mutable_pose()->mutable_translations() = local.translations();
    const v1::SkinMeshResponse expected = client.SkinMesh(by_pose);
    // The pose went through floats (1 part in 1e7 of 100 cm): well under a micrometre.
    const double position = MaxDifference(actual.positions(), expected.positions());
    const double normal = MaxDifference(actual.normals(), expected.normals());
    EXPECT_LT(position, 1e-3) << "t=" << t;
    EXPECT_LT(normal, 1e-5) << "t=" << t;

    // The character's own walk is the same motion keyed at 30 fps: at a
    // frame time both clips hold the same key. Each copy is held compressed
    // on its own under the default bound (0.01 cm at 3 cm from a joint), so
    // they may differ by up to twice it.
    v1::SkinMeshRequest own = by_clip;
    own.set_clip("demo_character.walk");
    const double own_difference = MaxDifference(actual.positions(), client.SkinMesh(own).positions());
    constexpr double kDefaultBoundCm = 0.01;
    EXPECT_LT(own_difference, 2 * kDefaultBoundCm) << "t=" << t;
    std::printf(
        "  t=%.1f: demo_walk on demo_character vs its EvaluateClip pose: %.2e cm (normals %.2e); vs "
        "demo_character.walk: %.2e cm\n",
        t, position, normal, own_difference);
  }

  // Streamed: the first frame is the unary answer at time 0.
  v1::StreamSkinnedMeshRequest stream;
  stream.set_mesh("demo_character.body");
  stream.set_clip("demo_walk");
  stream.set_fps(30);
  stream.set_duration(0.05);
  v1::SkinMeshRequest at_zero;
  at_zero.set_mesh("demo_character.body");
  at_zero.set_clip("demo_walk");
  const v1::SkinMeshResponse zero = client.SkinMesh(at_zero);
  int frames = 0;
  client.StreamSkinnedMesh(stream, [&](const v1::SkinnedMeshFrame& frame) {
    if (frames++ == 0) EXPECT_LT(MaxDifference(frame.positions(), zero.positions()), 1e-6);
    return true;
  });
  EXPECT_GE(frames, 1);
}

// demo_walk with its wrists renamed: the character's skeleton has joints
// that clip lacks.
TEST_F(ClipByName, AClipLackingJointsIsRefusedNamingThem) {
  ServerProcess server(data_.path());
  client::Client client(OptionsFor(server));
  std::string bvh = client.ExportClip("demo_walk").data();
  for (const std::string side : {"Left", "Right"}) {
    const std::string from = "JOINT " + side + "Wrist", to = "JOINT " + side + "Hand";
    const size_t at = bvh.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    bvh.replace(at, from.size(), to);
  }
  const auto path = WriteTemp(files_, "handed.bvh", bvh);
  client.ImportFile(path, "handed");
  v1::SkinMeshRequest r;
  r.set_mesh("demo_character.body");
  r.set_clip("handed");
  r.set_time(0.5);
  EXPECT_EQ(CodeOf([&] { client.SkinMesh(r); }), grpc::StatusCode::INVALID_ARGUMENT);
  const std::string message = MessageOf([&] { client.SkinMesh(r); });
  EXPECT_EQ(message,
            "clip: 'handed' animates skeleton 'handed', which lacks 2 of the 19 joints of the mesh's skeleton "
            "'demo_character': 'LeftWrist', 'RightWrist'");
  std::printf("  %s\n", message.c_str());
  // The IK's start pose follows the same rule.
  v1::SolveIkRequest ik;
  ik.set_skeleton("demo_character");
  ik.mutable_from_clip()->set_clip("handed");
  auto* e = ik.add_effectors();
  e->set_joint("LeftWrist");
  for (double v : {25.0, 100.0, 125.0}) e->add_target_position(v);
  EXPECT_EQ(MessageOf([&] { client.SolveIk(ik); }),
            "from_clip.clip: 'handed' animates skeleton 'handed', which lacks 2 of the 19 joints of "
            "'demo_character': 'LeftWrist', 'RightWrist'");
  ik.mutable_from_clip()->set_clip("demo_walk");
  ik.mutable_from_clip()->set_time(1.0);
  EXPECT_TRUE(client.SolveIk(ik).converged());
}

}  // namespace
}  // namespace armature::testing
