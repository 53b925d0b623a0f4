// Files the CLI writes and reads: `export -o` writes the format the file name
// says (BVH, glb, gltf), `--format` overrides the
// name on export and on import, and `skin -o` writes an OBJ.
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

class CliFiles : public ::testing::Test {
 protected:
  void SetUp() override { client::Client(OptionsFor(server_)).Import({"arm.bvh", kArmBvh}); }
  CommandResult Cli(const std::vector<std::string>& args) { return RunCli(server_.target(), args); }
  fs::path Out(const std::string& name) const { return files_.path() / name; }

  TempDir data_, files_;
  ServerProcess server_{data_.path()};  // with the demo assets: demo_character.body is skinned
};

TEST_F(CliFiles, ExportWritesTheFormatTheFileNameSays) {
  const std::string bvh = client::Client(OptionsFor(server_)).ExportClip("arm").data();
  ASSERT_NE(bvh.find("HIERARCHY"), std::string::npos);
  for (const std::string name : {"arm.bvh", "ARM.BVH"}) {
    const CommandResult r = Cli({"export", "arm", "-o", Out(name).string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(ReadFile(Out(name)), bvh) << name;
  }
  // --format overrides the extension.
  const CommandResult txt = Cli({"export", "arm", "-o", Out("arm.txt").string(), "--format", "bvh"});
  ASSERT_EQ(txt.exit_code, 0) << txt.err;
  EXPECT_EQ(ReadFile(Out("arm.txt")), bvh);
  // --json says what was written.
  const CommandResult j = Cli({"export", "arm", "-o", Out("j.bvh").string(), "--json"});
  ASSERT_EQ(j.exit_code, 0) << j.err;
  EXPECT_EQ(json::parse(j.out)["format"], "bvh");
  EXPECT_EQ(json::parse(j.out)["bytes"], bvh.size());
}

TEST_F(CliFiles, ExportWritesGltfWhenTheNameOrFormatSaysSo) {
  const CommandResult glb = Cli({"export", "arm", "-o", Out("arm.glb").string(), "--json"});
  ASSERT_EQ(glb.exit_code, 0) << glb.err;
  EXPECT_EQ(json::parse(glb.out)["format"], "glb");
  EXPECT_EQ(ReadFile(Out("arm.glb")).substr(0, 4), "glTF");
  const CommandResult gltf = Cli({"export", "arm", "-o", Out("arm.gltf").string()});
  ASSERT_EQ(gltf.exit_code, 0) << gltf.err;
  const json doc = json::parse(ReadFile(Out("arm.gltf")));
  EXPECT_EQ(doc["asset"]["version"], "2.0");
  EXPECT_EQ(doc["buffers"][0]["uri"].get<std::string>().rfind("data:application/octet-stream;base64,", 0), 0u);
  // --format glb over a .bvh name writes glTF.
  const CommandResult forced = Cli({"export", "arm", "-o", Out("a.bvh").string(), "--format", "glb"});
  ASSERT_EQ(forced.exit_code, 0) << forced.err;
  EXPECT_EQ(ReadFile(Out("a.bvh")).substr(0, 4), "glTF");
  // --with-meshes: the demo character's body and its skin come along.
  const CommandResult body = Cli({"export", "demo_character.walk", "-o", Out("walk.gltf").string(), "--with-meshes"});
  ASSERT_EQ(body.exit_code, 0) << body.err;
  const json character = json::parse(ReadFile(Out("walk.gltf")));
  ASSERT_EQ(character["meshes"].size(), 1u);
  EXPECT_EQ(character["meshes"][0]["name"], "body");
  EXPECT_EQ(character["skins"].size(), 1u);
  // …which BVH cannot hold: refused before any call, writing nothing.
  const CommandResult bvh_meshes = Cli({"export", "arm", "-o", Out("m.bvh").string(), "--with-meshes"});
  EXPECT_EQ(bvh_meshes.exit_code, 1);
  EXPECT_NE(bvh_meshes.err.find("--with-meshes needs glTF"), std::string::npos) << bvh_meshes.err;
  EXPECT_FALSE(fs::exists(Out("m.bvh")));
}

TEST_F(CliFiles, ExportRefusesUnknownExtensionsWritingNothing) {
  // No or an unknown extension: refused, naming the formats there are.
  for (const std::string name : {"arm.txt", "arm"}) {
    const CommandResult r = Cli({"export", "arm", "-o", Out(name).string()});
    EXPECT_EQ(r.exit_code, 1) << name;
    EXPECT_NE(r.err.find("cannot tell the export format"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--format glb|gltf|bvh"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(Out(name))) << name;
  }
  const CommandResult fbx = Cli({"export", "arm", "-o", Out("a.bvh").string(), "--format", "fbx"});
  EXPECT_NE(fbx.exit_code, 0);
  EXPECT_NE(fbx.err.find("bvh,glb,gltf"), std::string::npos) << fbx.err;
  // A server error leaves no file either.
  const CommandResult missing = Cli({"export", "nope", "-o", Out("nope.bvh").string()});
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("NOT_FOUND"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(Out("nope.bvh")));
}

TEST_F(CliFiles, ImportFormatOverridesTheFileName) {
  // BVH text under an .obj name: the name says OBJ, which fails.
  const fs::path file = WriteTemp(files_, "capture.obj", kArmBvh);
  const CommandResult by_name = Cli({"import", file.string()});
  EXPECT_EQ(by_name.exit_code, 1);
  EXPECT_NE(by_name.err.find("OBJ"), std::string::npos) << by_name.err;
  const CommandResult forced = Cli({"import", file.string(), "--format", "bvh"});
  ASSERT_EQ(forced.exit_code, 0) << forced.err;
  const json j = json::parse(forced.out);
  EXPECT_EQ(j["clips"][0]["name"], "capture");
  EXPECT_EQ(j["clips"][0]["frames"], 3);
  EXPECT_EQ(client::Client(OptionsFor(server_)).GetAsset("capture").format(), "bvh");
  const CommandResult unknown = Cli({"import", file.string(), "--format", "dae", "--name", "x"});
  EXPECT_NE(unknown.exit_code, 0);
  EXPECT_NE(unknown.err.find("bvh,gltf,glb,obj,fbx"), std::string::npos) << unknown.err;
}

TEST_F(CliFiles, SkinWritesAnObjThatImportsBack) {
  client::Client client(OptionsFor(server_));
  v1::SkinMeshRequest request;
  request.set_mesh("demo_character.body");
  request.set_clip("demo_character.walk");
  request.set_time(0.5);
  const auto skinned = client.SkinMesh(request);
  const auto geometry = client.GetMeshGeometry("demo_character.body");

  const fs::path obj = Out("walking.obj");
  const CommandResult r =
      Cli({"skin", "demo_character.body", "--clip", "demo_character.walk", "--time", "0.5", "-o", obj.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream lines(ReadFile(obj));
  std::string line;
  int v = 0, vn = 0, f = 0;
  while (std::getline(lines, line)) {
    std::istringstream in(line);
    std::string tag;
    in >> tag;
    if (tag == "v") {
      float x, y, z;
      in >> x >> y >> z;
      // The first vertex exactly (shortest round-trip text), the others by count.
      if (v == 0)
        EXPECT_EQ((std::vector<float>{x, y, z}),
                  (std::vector<float>(skinned.positions().begin(), skinned.positions().begin() + 3)));
      ++v;
    }
    if (tag == "vn") ++vn;
    if (tag == "f") {
      if (f == 0)
        EXPECT_EQ(line,
                  "f " + std::to_string(geometry.triangles(0) + 1) + "//" + std::to_string(geometry.triangles(0) + 1) +
                      " " + std::to_string(geometry.triangles(1) + 1) + "//" +
                      std::to_string(geometry.triangles(1) + 1) + " " + std::to_string(geometry.triangles(2) + 1) +
                      "//" + std::to_string(geometry.triangles(2) + 1));
      ++f;
    }
  }
  EXPECT_EQ(v, skinned.vertex_count());
  EXPECT_EQ(vn, skinned.vertex_count());
  EXPECT_EQ(f, geometry.triangles_size() / 3);
  const CommandResult back = Cli({"import", obj.string(), "--name", "statue"});
  ASSERT_EQ(back.exit_code, 0) << back.err;
  EXPECT_EQ(json::parse(back.out)["meshes"][0]["vertexCount"], skinned.vertex_count());

  const CommandResult ply = Cli(
      {"skin", "demo_character.body", "--clip", "demo_character.walk", "--time", "0.5", "-o", Out("w.ply").string()});
  EXPECT_EQ(ply.exit_code, 1);
  EXPECT_NE(ply.err.find("name a .obj file"), std::string::npos) << ply.err;
  EXPECT_FALSE(fs::exists(Out("w.ply")));
}

}  // namespace
}  // namespace armature::testing
