// The first-hour mistakes answered with a hint: a near-miss name ("did you mean"), an asset's name
// where a mesh's is wanted (its meshes listed), an unknown joint (the joints listed), an enum in
// lower case over REST (accepted), a wrong enum name (the allowed values listed).
#include <gtest/gtest.h>
#include <httplib.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

TEST(HelpfulErrors, NamesJointsAndEnumsOverGrpcAndRest) {
  TempDir data;
  ServerProcess server(data.path());
  client::Client client(OptionsFor(server));
  httplib::Client http("127.0.0.1", server.http_port());

  v1::EvaluateClipRequest typo;
  typo.set_clip("demo_wlak");
  typo.add_times(0);
  const grpc::Status clip = StatusOf([&] { client.EvaluateClip(typo); });
  EXPECT_EQ(clip.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(clip.error_message(), "clip 'demo_wlak' not found; did you mean 'demo_walk'?");

  const auto mesh = http.Get("/v1/meshes/demo_character");
  ASSERT_TRUE(mesh);
  EXPECT_EQ(mesh->status, 404) << mesh->body;
  EXPECT_NE(mesh->body.find("mesh 'demo_character' not found; asset 'demo_character' has meshes: demo_character.body"),
            std::string::npos)
      << mesh->body;

  const auto joint =
      http.Post("/v1/clips/demo_walk:evaluate", R"({"times":[0],"joints":["LeftWirst"]})", "application/json");
  ASSERT_TRUE(joint);
  EXPECT_EQ(joint->status, 404) << joint->body;
  EXPECT_NE(joint->body.find("joints[0]: unknown joint 'LeftWirst'; did you mean 'LeftWrist'? (the skeleton's 19 "
                             "joints: Hips, "),
            std::string::npos)
      << joint->body;

  const auto lower = http.Post("/v1/clips/demo_walk:evaluate", R"({"times":[0],"space":"world"})", "application/json");
  ASSERT_TRUE(lower);
  EXPECT_EQ(lower->status, 200) << lower->body;
  EXPECT_NE(lower->body.find("\"space\":\"WORLD\""), std::string::npos) << lower->body;

  const auto wrong = http.Post("/v1/clips/demo_walk:evaluate", R"({"times":[0],"space":"global"})", "application/json");
  ASSERT_TRUE(wrong);
  EXPECT_EQ(wrong->status, 400) << wrong->body;
  EXPECT_NE(wrong->body.find("allowed: SPACE_UNSPECIFIED, LOCAL, WORLD (any case)"), std::string::npos) << wrong->body;
}

}  // namespace
}  // namespace armature::testing
