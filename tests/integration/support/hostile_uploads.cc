#include "support/hostile_uploads.h"

#include <filesystem>
#include <random>

#include <nlohmann/json.hpp>

#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/demo_character.h"
#include "armature/engine/io/demo_walk.h"
#include "support/client_helpers.h"
#include "support/deform_grid.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {
using nlohmann::json;

// A tiny valid glTF: one triangle (positions in a data: buffer), a node
// with it, and a skinless one-node animation the bombs can stretch.
json TinyGltf() {
  // 3 vec3 floats (0,0,0) (1,0,0) (0,1,0), then 2 scalar times 0 and 1, then 2 vec3 translations.
  const char* kBuffer =
      "data:application/octet-stream;base64,"
      "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAA=";
  return json{
      {"asset", {{"version", "2.0"}}},
      {"buffers", {{{"uri", kBuffer}, {"byteLength", 68}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}},
        {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 8}},
        {{"buffer", 0}, {"byteOffset", 44}, {"byteLength", 24}}}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", 3},
         {"type", "VEC3"},
         {"min", {0, 0, 0}},
         {"max", {1, 1, 0}}},
        {{"bufferView", 1}, {"componentType", 5126}, {"count", 2}, {"type", "SCALAR"}, {"min", {0}}, {"max", {1}}},
        {{"bufferView", 2}, {"componentType", 5126}, {"count", 2}, {"type", "VEC3"}}}},
      {"meshes", {{{"name", "tri"}, {"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}}},
      {"nodes", {{{"name", "root"}, {"mesh", 0}}}},
      {"scenes", {{{"nodes", {0}}}}},
      {"scene", 0},
      {"animations",
       {{{"name", "move"},
         {"samplers", {{{"input", 1}, {"output", 2}}}},
         {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}}}}};
}

std::string Glb(const std::string& json_text, const std::string& bin, uint32_t claimed_bin_length) {
  std::string j = json_text;
  while (j.size() % 4) j += ' ';
  std::string b = bin;
  while (b.size() % 4) b += '\0';
  auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  const uint32_t total = static_cast<uint32_t>(12 + 8 + j.size() + 8 + b.size());
  return "glTF" + u32(2) + u32(total) + u32(static_cast<uint32_t>(j.size())) + "JSON" + j + u32(claimed_bin_length) +
         "BIN" + std::string(1, '\0') + b;
}

HostileUpload Bomb(const std::string& shape, const std::string& filename, std::string bytes) {
  return {"bomb:" + shape, filename, std::move(bytes)};
}

// Real files to truncate and flip bits in.
std::vector<HostileUpload> RealFiles() {
  std::vector<HostileUpload> files;
  files.push_back({"", "arm.bvh", kArmBvh});
  files.push_back({"", "walk.bvh", WriteBvh(*MakeDemoWalk().clip)});
  if (auto glb = MakeDemoCharacterGlb(); glb.ok()) files.push_back({"", "character.glb", *glb});
  files.push_back({"", "grid.obj", MakeGrid(12).obj});
  files.push_back({"", "tiny.gltf", TinyGltf().dump()});
  for (const char* shared :
       {"bvh/cmu_01_01.bvh", "gltf/rigged_simple.gltf", "gltf/simple_skin.gltf", "gltf/interpolation_test.gltf",
        "gltf/RobotExpressive/RobotExpressive.glb", "fbx/animation_with_skeleton.fbx", "fbx/box_ascii.fbx"}) {
    const std::string path = SharedData(shared);
    if (!path.empty() && std::filesystem::exists(path))
      files.push_back({"", std::filesystem::path(path).filename().string(), ReadFile(path)});
  }
  return files;
}

}  // namespace

std::vector<HostileUpload> BombUploads() {
  std::vector<HostileUpload> bombs;
  {
    // A BVH of 2,000 nested joints claiming two billion frames (with three).
    std::string bvh =
        "HIERARCHY\nROOT j0\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation "
        "Yrotation\n";
    constexpr int kJoints = 2000;
    for (int i = 1; i < kJoints; ++i)
      bvh += "JOINT j" + std::to_string(i) + "\n{\nOFFSET 0 1 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n";
    bvh += "End Site\n{\nOFFSET 0 1 0\n}\n";
    for (int i = 0; i < kJoints; ++i) bvh += "}\n";
    bvh += "MOTION\nFrames: 2000000000\nFrame Time: 0.0333333\n";
    std::string frame;
    for (int c = 0; c < 6 + 3 * (kJoints - 1); ++c) frame += "0 ";
    for (int f = 0; f < 3; ++f) bvh += frame + "\n";
    bombs.push_back(Bomb("bvh-huge-frames-many-joints", "bomb.bvh", bvh));
  }
  {
    json g = TinyGltf();
    g["accessors"][0]["byteOffset"] = 18446744073709551000ull;
    bombs.push_back(Bomb("gltf-byteoffset-2^64", "bomb.gltf", g.dump()));
  }
  {
    json g = TinyGltf();
    g["accessors"][0].erase("bufferView");
    g["accessors"][0]["count"] = 268435456;
    bombs.push_back(Bomb("gltf-accessor-no-bufferview-count-2^28", "bomb.gltf", g.dump()));
  }
  {
    json g = TinyGltf();
    g["accessors"].push_back(
        {{"componentType", 5126}, {"count", 268435456}, {"type", "VEC3"}});  // zeros, no bufferView
    const int huge = static_cast<int>(g["accessors"].size()) - 1;
    g["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = huge;
    json targets = json::array();
    for (int t = 0; t < 1000; ++t) targets.push_back({{"POSITION", huge}});
    g["meshes"][0]["primitives"][0]["targets"] = targets;
    g["meshes"][0]["weights"] = std::vector<double>(1000, 0.0);
    bombs.push_back(Bomb("gltf-1000-morph-targets-huge-vertex-count", "bomb.gltf", g.dump()));
  }
  {
    json g = TinyGltf();
    g["accessors"][1].erase("bufferView");
    g["accessors"][1]["count"] = 268435456;
    g["accessors"][2].erase("bufferView");
    g["accessors"][2]["count"] = 268435456;
    bombs.push_back(Bomb("gltf-animation-input-count-2^28", "bomb.gltf", g.dump()));
  }
  {
    json g = TinyGltf();
    const std::string bin(68, '\0');
    g["buffers"][0].erase("uri");
    bombs.push_back(Bomb("glb-bin-chunk-length-lies", "bomb.glb", Glb(g.dump(), bin, 0xFFFFFFF0u)));
  }
  {
    // A binary FBX whose first record's lengths run past the file: assimp's
    // tokenizer fails its own check, which aborted the process.
    std::string fbx = "Kaydara FBX Binary# a te\no t";
    fbx += std::string(7, '\0') + "\x01hi" + std::string(58, '\xff') + "h\nHI";
    fbx.resize(500, 'x');
    bombs.push_back(Bomb("fbx-record-past-the-file-fails-an-assimp-check", "bomb.fbx", fbx));
  }
  {
    // An ASCII FBX of 20,000 objects connected in one chain, and scopes
    // nested 30,000 deep: assimp recursed through either until the stack
    // overflowed.
    std::string chain = "; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n\tFBXVersion: 7400\n}\nObjects:  {\n";
    constexpr int kChain = 20000;
    for (int i = 1; i <= kChain; ++i) chain += "\tModel: " + std::to_string(i) + ", \"Model::m\", \"Null\" {\n\t}\n";
    chain += "}\nConnections:  {\n";
    for (int i = 1; i <= kChain; ++i) chain += "\tC: \"OO\"," + std::to_string(i) + "," + std::to_string(i - 1) + "\n";
    bombs.push_back(Bomb("fbx-chain-of-20000-objects", "bomb.fbx", chain + "}\n"));
    std::string scopes = "; FBX 7.4.0 project file\nFoo:  {\n";
    for (int i = 0; i < 30000; ++i) scopes += "a: {";
    bombs.push_back(Bomb("fbx-scopes-nested-30000-deep", "bomb.fbx", scopes + std::string(30001, '}')));
  }
  return bombs;
}

std::vector<HostileUpload> HostileUploads(int count, uint32_t seed) {
  std::mt19937 rng(seed);
  const std::vector<HostileUpload> bombs = BombUploads();
  const std::vector<HostileUpload> real = RealFiles();
  const char* kExtensions[] = {".bvh", ".gltf", ".glb", ".obj", ".fbx", ".bin", ""};
  std::vector<HostileUpload> out;
  const int bomb_every = std::max(1, count / static_cast<int>(4 * bombs.size()));  // each bomb about 4 times
  for (int i = 0; i < count; ++i) {
    if (i % bomb_every == 0) {
      out.push_back(bombs[(i / bomb_every) % bombs.size()]);
      continue;
    }
    switch (rng() % 3) {
      case 0: {
        std::string bytes(1 + rng() % (64 << 10), '\0');
        for (char& c : bytes) c = static_cast<char>(rng());
        out.push_back({"random", std::string("random") + kExtensions[rng() % 7], std::move(bytes)});
        break;
      }
      case 1: {
        const HostileUpload& f = real[rng() % real.size()];
        out.push_back({"truncated", f.filename, f.bytes.substr(0, rng() % f.bytes.size())});
        break;
      }
      default: {
        const HostileUpload& f = real[rng() % real.size()];
        std::string bytes = f.bytes;
        const int flips = 1 + static_cast<int>(rng() % 16);
        for (int k = 0; k < flips; ++k) bytes[rng() % bytes.size()] ^= static_cast<char>(1u << (rng() % 8));
        out.push_back({"bitflip", f.filename, std::move(bytes)});
      }
    }
    if (out.back().bytes.empty()) out.back().bytes = "x";  // an empty file is refused before any parsing
  }
  return out;
}

}  // namespace armature::testing
