// A glTF's resources are stored one file each, whatever their uris: uris whose
// last parts are the same ("a/data.bin", "b/data.bin") or sanitize alike
// ("a b.bin", "a_b.bin") once shared one file, so the first was overwritten
// and the acknowledged import was skipped at the next start.
#include <csignal>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "armature/engine/io/demo_character.h"
#include "support/client_helpers.h"
#include "support/data_dir_check.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

// The demo character as a .gltf whose real buffer is `real_uri`, with a
// second, unused 8-byte buffer at `other_uri`.
client::UploadFile GltfWithTwoBuffers(const SplitGltf& character, const std::string& real_uri,
                                      const std::string& other_uri) {
  auto doc = nlohmann::json::parse(character.gltf);
  doc["buffers"][0]["uri"] = real_uri;
  doc["buffers"].push_back({{"uri", other_uri}, {"byteLength", 8}});
  return {"character.gltf", doc.dump()};
}

TEST(ResourceNames, ResourcesWhoseNamesEndAlikeSurviveARestart) {
  auto glb = MakeDemoCharacterGlb();
  ASSERT_TRUE(glb.ok()) << glb.status().message();
  const SplitGltf character = SplitGlb(*glb, "placeholder");
  const std::string eight(8, 'x');
  TempDir data;
  const std::pair<std::string, std::string> pairs[] = {{"a/data.bin", "b/data.bin"}, {"a b.bin", "a_b.bin"}};
  std::set<std::string> clips_before;
  {
    ServerProcess server(data.path(), {"--no-demo"});
    client::Client client(OptionsFor(server));
    int i = 0;
    for (const auto& [real, other] : pairs) {
      const auto imported = client.Import(GltfWithTwoBuffers(character, real, other), "pair" + std::to_string(i++), "",
                                          false, {{real, character.bin}, {other, eight}});
      EXPECT_GT(imported.asset().meshes_size(), 0) << real << " + " << other;
    }
    const auto clips = client.ListClips();
    for (const auto& c : clips.clips()) clips_before.insert(c.name());
    EXPECT_EQ(server.Stop(SIGTERM), 0);
  }
  ServerProcess server(data.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  EXPECT_EQ(AssetNames(client), (std::set<std::string>{"pair0", "pair1"})) << "an acknowledged import was lost";
  std::set<std::string> clips_after;
  const auto clips = client.ListClips();
  for (const auto& c : clips.clips()) clips_after.insert(c.name());
  EXPECT_EQ(clips_after, clips_before);
  const auto meshes = client.ListMeshes();
  EXPECT_GE(meshes.meshes_size(), 2);
  for (const auto& mesh : meshes.meshes())
    EXPECT_GT(client.GetMeshGeometry(mesh.name()).positions_size(), 0) << mesh.name();
}

}  // namespace
}  // namespace armature::testing
