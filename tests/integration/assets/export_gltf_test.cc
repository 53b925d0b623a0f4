// ExportClip as glTF: a .glb of the demo character's walk with its mesh,
// imported back into the server, plays the same local poses; the format is
// checked (unknown → INVALID_ARGUMENT listing the allowed ones; meshes need
// glTF); REST takes the format and withMeshes as query parameters.
#include <cmath>
#include <string>

// The engine first: a system header included later defines a macro Eigen's
// headers trip on.
#include "armature/engine/io/gltf/gltf.h"
#include "armature/engine/mesh/mesh.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

v1::EvaluateClipResponse Local(client::Client& client, const std::string& clip, const std::vector<double>& times) {
  v1::EvaluateClipRequest r;
  r.set_clip(clip);
  for (double t : times) r.add_times(t);
  r.set_space(v1::LOCAL);
  return client.EvaluateClip(r);
}

TEST(ExportGltf, AGlbWithMeshesImportsBackAndPlaysTheSamePoses) {
  TempDir data;
  ServerProcess server(data.path());  // with the demo assets
  client::Client client(OptionsFor(server));
  const auto glb = client.ExportClip("demo_character.walk", "glb", true);
  EXPECT_EQ(glb.filename(), "demo_character.walk.glb");
  ASSERT_EQ(glb.data().substr(0, 4), "glTF");
  auto contents = ParseGltf(glb.data(), true, "back");
  ASSERT_TRUE(contents.ok()) << contents.status().message();
  ASSERT_EQ(contents->meshes.size(), 1u);
  EXPECT_EQ(contents->meshes[0].name, "back.body");
  EXPECT_TRUE(contents->meshes[0].mesh->skinned());
  ASSERT_EQ(contents->clips.size(), 1u);
  EXPECT_EQ(contents->clips[0].name, "back.walk");

  client.Import({glb.filename(), glb.data()}, "back");
  const std::vector<double> times = {0, 0.25, 1.0 / 3, 1.7, 2.9};
  const auto want = Local(client, "demo_character.walk", times), got = Local(client, "back.walk", times);
  ASSERT_EQ(got.poses_size(), want.poses_size());
  for (int i = 0; i < want.poses_size(); ++i) {
    ASSERT_EQ(got.poses(i).translations_size(), want.poses(i).translations_size());
    for (int k = 0; k < want.poses(i).translations_size(); ++k) {
      const double v = want.poses(i).translations(k);
      // The import compresses the exported samples again under the default bound (1e-4 m for glTF):
      // the samples come back within it, not bit for bit.
      EXPECT_NEAR(got.poses(i).translations(k), v, 1e-6 * std::max(1.0, std::abs(v)) + 1e-4) << "t=" << times[i];
    }
    for (int k = 0; k < want.poses(i).rotations_size(); k += 4) {
      double dot = 0;
      for (int c = 0; c < 4; ++c) dot += got.poses(i).rotations(k + c) * want.poses(i).rotations(k + c);
      EXPECT_NEAR(std::abs(dot), 1.0, 1e-6) << "t=" << times[i] << " joint " << k / 4;
    }
  }
  // Without meshes: the skeleton and the animation only.
  auto bare = ParseGltf(client.ExportClip("demo_character.walk", "glb").data(), true, "bare");
  ASSERT_TRUE(bare.ok()) << bare.status().message();
  EXPECT_TRUE(bare->meshes.empty());
  EXPECT_EQ(bare->clips.size(), 1u);
  // BVH stays the default.
  const auto bvh = client.ExportClip("demo_character.walk");
  EXPECT_EQ(bvh.filename(), "demo_character.walk.bvh");
  EXPECT_EQ(bvh.data().substr(0, 9), "HIERARCHY");
}

TEST(ExportGltf, BadFormatsAreInvalidArgumentNamingTheField) {
  TempDir data;
  ServerProcess server(data.path());
  client::Client client(OptionsFor(server));
  const grpc::Status fbx = StatusOf([&] { client.ExportClip("demo_walk", "fbx"); });
  EXPECT_EQ(fbx.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(fbx.error_message(), "format: unknown export format 'fbx'; allowed: bvh, glb, gltf");
  const grpc::Status meshes = StatusOf([&] { client.ExportClip("demo_walk", "bvh", true); });
  EXPECT_EQ(meshes.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(meshes.error_message().find("with_meshes"), std::string::npos) << meshes.error_message();
  EXPECT_EQ(StatusOf([&] { client.ExportClip("nope", "glb"); }).error_code(), grpc::StatusCode::NOT_FOUND);
}

TEST(ExportGltf, RestTakesFormatAndWithMeshesAsQueryParameters) {
  TempDir data;
  ServerProcess server(data.path());
  httplib::Client http("127.0.0.1", server.http_port());
  const auto r = http.Get("/v1/clips/demo_character.walk:export?format=gltf&withMeshes=true");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const auto body = nlohmann::json::parse(r->body);
  EXPECT_EQ(body["filename"], "demo_character.walk.gltf");
  EXPECT_FALSE(body["data"].get<std::string>().empty());  // base64 of the .gltf JSON
  const auto bad = http.Get("/v1/clips/demo_walk:export?format=fbx");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400) << bad->body;
  EXPECT_NE(bad->body.find("allowed: bvh, glb, gltf"), std::string::npos) << bad->body;
}

TEST(ExportGltf, IsRefusedOverTheReplyLimitBeforeWriting) {
  TempDir data;
  ServerProcess server(data.path(), {"--max-message-mb", "0.05"});
  client::Client client(OptionsFor(server));
  // The body: thousands of vertices with normals, skin and indices, well over 51 KB.
  const grpc::Status refused = StatusOf([&] { client.ExportClip("demo_character.walk", "glb", true); });
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << refused.error_message();
  EXPECT_NE(refused.error_message().find("--max-message-mb"), std::string::npos) << refused.error_message();
  EXPECT_NE(refused.error_message().find("1 meshes"), std::string::npos) << refused.error_message();
}

}  // namespace
}  // namespace armature::testing
