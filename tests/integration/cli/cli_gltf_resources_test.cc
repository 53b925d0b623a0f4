// `armature import` uploads a .gltf's buffers only from the .gltf's folder
// (and its subfolders): a malicious .gltf naming /etc/passwd, ../secret or a
// file: uri must not make the CLI send that file to a server, unless the
// user says so with --allow-outside-resources.
#include <filesystem>
#include <fstream>
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
namespace fs = std::filesystem;

class CliGltfResources : public ::testing::Test {
 protected:
  void SetUp() override {
    auto glb = MakeDemoCharacterGlb();
    ASSERT_TRUE(glb.ok()) << glb.status().message();
    character_ = SplitGlb(*glb, "placeholder");
    folder_ = files_.path() / "model";
    fs::create_directories(folder_ / "buffers");
    std::ofstream(files_.path() / "secret.bin", std::ios::binary) << character_.bin;  // outside the folder
    std::ofstream(folder_ / "buffers" / "body.bin", std::ios::binary) << character_.bin;
  }

  // A .gltf in the model folder whose buffer uri is `uri`.
  std::string WriteGltf(const std::string& name, const std::string& uri) {
    auto doc = nlohmann::json::parse(character_.gltf);
    doc["buffers"][0]["uri"] = uri;
    const fs::path path = folder_ / (name + ".gltf");
    std::ofstream(path) << doc.dump();
    return path.string();
  }

  TempDir data_, files_;
  SplitGltf character_;
  fs::path folder_;
};

TEST_F(CliGltfResources, OnlyFilesInTheGltfsFolderAreUploaded) {
  ServerProcess server(data_.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));

  // In a subfolder: uploaded, and the import works.
  const auto ok = RunCli(server.target(), {"import", WriteGltf("inside", "buffers/body.bin")});
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(AssetNames(client), std::set<std::string>{"inside"});

  fs::create_symlink(files_.path() / "secret.bin", folder_ / "link.bin");
  const std::string refused[] = {"/etc/passwd",
                                 "../secret.bin",
                                 "buffers/../../secret.bin",
                                 "%2e%2e/secret.bin",
                                 "file://" + (files_.path() / "secret.bin").string(),
                                 "file:../secret.bin",
                                 "link.bin"};
  int i = 0;
  for (const std::string& uri : refused) {
    const auto r = RunCli(server.target(), {"import", WriteGltf("evil" + std::to_string(i++), uri)});
    EXPECT_NE(r.exit_code, 0) << uri << " was uploaded";
    EXPECT_NE(r.err.find("'" + uri + "'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--allow-outside-resources"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("root:"), std::string::npos) << "the server saw /etc/passwd: " << r.err;
  }
  EXPECT_EQ(AssetNames(client), std::set<std::string>{"inside"}) << "a refused import reached the server";

  // The user may lift the rule for a file they mean to send.
  const auto allowed =
      RunCli(server.target(), {"import", "--allow-outside-resources", WriteGltf("allowed", "../secret.bin")});
  EXPECT_EQ(allowed.exit_code, 0) << allowed.err;
  const auto absolute =
      RunCli(server.target(), {"import", "--allow-outside-resources",
                               WriteGltf("absolute", "file://" + (files_.path() / "secret.bin").string())});
  EXPECT_EQ(absolute.exit_code, 0) << absolute.err;
  EXPECT_EQ(AssetNames(client), (std::set<std::string>{"inside", "allowed", "absolute"}));
}

}  // namespace
}  // namespace armature::testing
