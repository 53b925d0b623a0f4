// Malformed keys: each is INVALID_ARGUMENT (or NOT_FOUND / RESOURCE_EXHAUSTED)
// naming the entry, the joint, the key index and the problem; nothing is stored.
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "authoring/create_clip_support.h"
#include "support/client_helpers.h"
#include "support/server_suite.h"

namespace armature::testing {
namespace {

class CreateClipValidation : public ServerSuite {
 protected:
  // A good request: Head with three LINEAR keys.
  static v1::CreateClipRequest Good() {
    v1::CreateClipRequest r;
    r.set_skeleton("demo_walk");
    r.set_name("bad");
    const Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    *r.add_tracks() = Keys("Neck", {0, 0.5}, {q, q}, {}, v1::LINEAR);
    *r.add_tracks() = Keys("Head", {0, 0.5, 1}, {q, q, q},
                           {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}, v1::LINEAR);
    return r;
  }
};

struct BadCase {
  const char* what;
  std::function<void(v1::CreateClipRequest&)> mutate;
  grpc::StatusCode code;
  std::vector<std::string> mentions;  // substrings the message must hold
};

// Each malformed key of a good request (tracks[1] is Head's), with what its
// refusal must name.
std::vector<BadCase> MalformedKeyCases() {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  auto head = [](v1::CreateClipRequest& r) { return r.mutable_tracks(1); };
  const grpc::StatusCode invalid = grpc::StatusCode::INVALID_ARGUMENT;
  return {
      {"unknown joint",
       [=](auto& r) { head(r)->set_joint("Haed"); },
       invalid,
       {"tracks[1]", "'Haed'", "not on skeleton 'demo_walk'", "did you mean 'Head'"}},
      {"unsorted times",
       [=](auto& r) { head(r)->set_times(2, 0.25); },
       invalid,
       {"tracks[1] (joint 'Head')", "key 2", "does not increase", "sorted"}},
      {"duplicate times",
       [=](auto& r) { head(r)->set_times(1, 0); },
       invalid,
       {"joint 'Head'", "key 1", "repeats key 0"}},
      {"times equal as floats",
       [=](auto& r) { head(r)->set_times(2, 0.5 + 1e-9); },
       invalid,
       {"joint 'Head'", "key 2", "32-bit float"}},
      {"negative time", [=](auto& r) { head(r)->set_times(0, -1); }, invalid, {"joint 'Head'", "key 0", "negative"}},
      {"NaN time", [=](auto& r) { head(r)->set_times(1, nan); }, invalid, {"joint 'Head'", "key 1", "not finite"}},
      {"NaN rotation",
       [=](auto& r) { head(r)->set_rotations(5, nan); },
       invalid,
       {"joint 'Head'", "key 1", "rotations", "not finite"}},
      {"Inf translation",
       [=](auto& r) { head(r)->set_translations(8, inf); },
       invalid,
       {"joint 'Head'", "key 2", "translations", "not finite"}},
      {"non-unit quaternion",
       [=](auto& r) { head(r)->set_rotations(4, 1.01); },
       invalid,
       {"joint 'Head'", "key 1", "not a unit quaternion", "norm 1.01"}},
      {"zero quaternion",
       [=](auto& r) {
         for (int c = 0; c < 4; ++c) head(r)->set_rotations(8 + c, 0);
       },
       invalid,
       {"joint 'Head'", "key 2", "not a unit quaternion"}},
      {"rotation count",
       [=](auto& r) { head(r)->add_rotations(0); },
       invalid,
       {"joint 'Head'", "rotations: 13 values for 3 keys", "4 per key (w, x, y, z)"}},
      {"translation count",
       [=](auto& r) { head(r)->mutable_translations()->RemoveLast(); },
       invalid,
       {"joint 'Head'", "translations: 8 values for 3 keys", "3 per key"}},
      {"unknown interpolation",
       [=](auto& r) { head(r)->set_interpolation(static_cast<v1::Interpolation>(9)); },
       invalid,
       {"tracks[1] (joint 'Head').interpolation", "9"}},
  };
}

// The rotations given as Euler angles, tangents, and the track and request as a whole.
std::vector<BadCase> MalformedTrackCases() {
  auto head = [](v1::CreateClipRequest& r) { return r.mutable_tracks(1); };
  const grpc::StatusCode invalid = grpc::StatusCode::INVALID_ARGUMENT;
  return {
      {"unknown Euler order",
       [=](auto& r) {
         head(r)->clear_rotations();
         for (int i = 0; i < 9; ++i) head(r)->add_euler(0);
         head(r)->set_euler_order("XQZ");
       },
       invalid,
       {"joint 'Head'", "euler_order", "XQZ"}},
      {"Euler order with an axis twice",
       [=](auto& r) {
         head(r)->clear_rotations();
         for (int i = 0; i < 9; ++i) head(r)->add_euler(0);
         head(r)->set_euler_order("XXX");
       },
       invalid,
       {"joint 'Head'", "euler_order", "once each", "XXX"}},
      {"proper Euler order",
       [=](auto& r) {
         head(r)->clear_rotations();
         for (int i = 0; i < 9; ++i) head(r)->add_euler(0);
         head(r)->set_euler_order("zxz");
       },
       invalid,
       {"joint 'Head'", "euler_order", "zxz"}},
      {"Euler count",
       [=](auto& r) {
         head(r)->clear_rotations();
         for (int i = 0; i < 8; ++i) head(r)->add_euler(0);
       },
       invalid,
       {"joint 'Head'", "euler: 8 values for 3 keys"}},
      {"rotations and Euler",
       [=](auto& r) {
         for (int i = 0; i < 9; ++i) head(r)->add_euler(0);
       },
       invalid,
       {"joint 'Head'", "both rotations and euler"}},
      {"tangents on a LINEAR track",
       [=](auto& r) {
         for (int i = 0; i < 9; ++i) head(r)->mutable_translation_tangents()->add_in_tangents(0);
       },
       invalid,
       {"joint 'Head'", "translation_tangents", "only for CUBIC"}},
      {"tangent count",
       [=](auto& r) {
         head(r)->set_interpolation(v1::CUBIC);
         for (int i = 0; i < 9; ++i) head(r)->mutable_translation_tangents()->add_in_tangents(0);
       },
       invalid,
       {"joint 'Head'", "translation_tangents.outTangents: 0 values for 3 keys"}},
      {"values without times", [=](auto& r) { head(r)->clear_times(); }, invalid, {"joint 'Head'", "without times"}},
      {"times without values",
       [=](auto& r) {
         head(r)->clear_rotations();
         head(r)->clear_translations();
       },
       invalid,
       {"joint 'Head'", "times without values"}},
      {"empty track without merge",
       [=](auto& r) {
         head(r)->clear_rotations();
         head(r)->clear_translations();
         head(r)->clear_times();
       },
       invalid,
       {"joint 'Head'", "no times", "merge"}},
      {"a joint twice",
       [=](auto& r) { head(r)->set_joint("Neck"); },
       invalid,
       {"tracks[1] (joint 'Neck')", "second entry"}},
      {"no joint name", [=](auto& r) { head(r)->clear_joint(); }, invalid, {"tracks[1]", "joint is empty"}},
      {"no tracks", [=](auto& r) { r.clear_tracks(); }, invalid, {"no keys"}},
      {"no skeleton", [=](auto& r) { r.clear_skeleton(); }, invalid, {"skeleton", "required"}},
      {"no name", [=](auto& r) { r.clear_name(); }, invalid, {"name"}},
      {"unknown skeleton",
       [=](auto& r) { r.set_skeleton("demo_wlak"); },
       grpc::StatusCode::NOT_FOUND,
       {"skeleton 'demo_wlak'", "did you mean 'demo_walk'"}},
  };
}

TEST_F(CreateClipValidation, EachMalformedKeyIsNamed) {
  std::vector<BadCase> cases = MalformedKeyCases();
  for (BadCase& c : MalformedTrackCases()) cases.push_back(std::move(c));
  client::Client client(OptionsFor(*server_));
  for (const BadCase& c : cases) {
    v1::CreateClipRequest r = Good();
    c.mutate(r);
    const grpc::Status status = StatusOf([&] { client.CreateClip(r); });
    EXPECT_EQ(status.error_code(), c.code) << c.what << ": " << status.error_message();
    for (const std::string& m : c.mentions)
      EXPECT_NE(status.error_message().find(m), std::string::npos)
          << c.what << ": '" << m << "' not in: " << status.error_message();
  }
  // Nothing was stored; the good request itself is accepted.
  EXPECT_EQ(CodeOf([&] { client.GetAsset("bad"); }), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(client.CreateClip(Good()).clip().name(), "bad");
}

TEST(CreateClipLimits, KeysOverMaxClipFramesAreResourceExhaustedNamingTheFlag) {
  TempDir data;
  // The demo walk (91 frames) is over this limit: a small BVH arm instead.
  ServerProcess server(data.path(), {"--max-clip-frames", "10"});
  client::Client client(OptionsFor(server));
  client.Import({"arm.bvh", kArmBvh}, "arm");
  v1::CreateClipRequest r;
  r.set_skeleton("arm");
  r.set_name("long");
  v1::JointKeys* k = r.add_tracks();
  k->set_joint("Tip");
  for (int i = 0; i < 11; ++i) {
    k->add_times(0.1 * i);
    for (double c : {1.0, 0.0, 0.0, 0.0}) k->add_rotations(c);
  }
  const grpc::Status status = StatusOf([&] { client.CreateClip(r); });
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
  EXPECT_NE(status.error_message().find("--max-clip-frames"), std::string::npos) << status.error_message();
  EXPECT_NE(status.error_message().find("joint 'Tip'"), std::string::npos) << status.error_message();
  k->mutable_times()->RemoveLast();
  k->mutable_rotations()->Truncate(40);
  EXPECT_EQ(client.CreateClip(r).clip().frames(), 10);
}

}  // namespace
}  // namespace armature::testing
