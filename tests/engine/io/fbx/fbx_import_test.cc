// FBX import (assimp) on the shared files and on broken bytes: what the
// skeleton, clips and meshes hold, the units report, format detection, limits
// and clear errors.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <vector>
#include <string>

#include <gtest/gtest.h>

#include "armature/engine/io/asset.h"
#include "armature/engine/io/fbx/fbx.h"
#include "armature/engine/mesh/mesh.h"
#include "../../testing/test_files.h"

namespace armature {
namespace {

namespace fs = std::filesystem;
using test_util::ReadFileBytes;
using test_util::SharedData;

std::string Shared(const std::string& file) {
  const auto bytes = ReadFileBytes(SharedData("fbx/" + file));
  return bytes.value_or("");
}

bool HasWarning(const AssetContents& c, const std::string& part) {
  for (const auto& w : c.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

TEST(FbxImport, AnimatedArmatureKeepsItsBonesClipAndSkin) {
  const std::string bytes = Shared("animation_with_skeleton.fbx");
  if (bytes.empty()) GTEST_SKIP() << "shared data not found";
  auto c = ParseAsset(AssetFormat::kFbx, bytes, "arm");
  ASSERT_TRUE(c.ok()) << c.status().message();
  ASSERT_EQ(c->skeletons.size(), 1u);
  const Skeleton& s = *c->skeletons[0].skeleton;
  // Cube, Light, Camera, Armature and its 14 bones with their two end bones:
  // no "RootNode", no "$AssimpFbx$" helper.
  EXPECT_EQ(s.size(), 20u);
  for (const auto& n : s.names) EXPECT_EQ(n.find("$AssimpFbx$"), std::string::npos) << n;
  EXPECT_EQ(s.Find("RootNode"), -1);
  ASSERT_GE(s.Find("Bone.006"), 0);
  EXPECT_EQ(s.names[static_cast<size_t>(s.parents[static_cast<size_t>(s.Find("Bone.006"))])], "Bone.005");
  ASSERT_EQ(c->clips.size(), 1u);
  EXPECT_EQ(c->clips[0].name, "arm.Armature|ArmatureAction");
  EXPECT_EQ(c->clips[0].skeleton_name, "arm");
  EXPECT_NEAR(c->clips[0].clip->duration, 20.0 / 24.0, 1e-9);  // 20 frames at 24 fps
  ASSERT_EQ(c->meshes.size(), 1u);
  const Mesh& m = *c->meshes[0].mesh;
  EXPECT_EQ(c->meshes[0].name, "arm.Cube.001");
  EXPECT_EQ(m.vertex_count(), 2464u);
  EXPECT_EQ(m.triangle_count(), 2112u);
  EXPECT_EQ(m.joints.size(), 14u);  // the 14 deforming bones (every vertex weighted)
  EXPECT_TRUE(HasWarning(*c, "FBX units: 1 unit = 1 cm (UnitScaleFactor 1), centimetres; up axis +Y"));
}

TEST(FbxImport, BinaryAndAsciiBoxesAndTheirUnits) {
  const std::string binary = Shared("box.fbx"), ascii = Shared("box_ascii.fbx");
  if (binary.empty() || ascii.empty()) GTEST_SKIP() << "shared data not found";
  EXPECT_TRUE(LooksLikeFbx(binary));
  EXPECT_TRUE(LooksLikeFbx(ascii));
  EXPECT_EQ(*DetectFormat("", "upload.bin", binary), AssetFormat::kFbx);
  EXPECT_EQ(*DetectFormat("", "upload.bin", ascii), AssetFormat::kFbx);
  EXPECT_EQ(*DetectFormat("", "x.FBX", ""), AssetFormat::kFbx);
  EXPECT_EQ(*DetectFormat("fbx", "x.glb", ""), AssetFormat::kFbx);
  for (const std::string* bytes : {&binary, &ascii}) {
    auto c = ParseAsset(AssetFormat::kFbx, *bytes, "box");
    ASSERT_TRUE(c.ok()) << c.status().message();
    ASSERT_EQ(c->meshes.size(), 1u);
    EXPECT_EQ(c->meshes[0].mesh->vertex_count(), 24u);  // 6 faces × 4 corners (normals differ)
    EXPECT_EQ(c->meshes[0].mesh->triangle_count(), 12u);
    // The mesh follows its node rigidly.
    EXPECT_EQ(c->meshes[0].mesh->joints.size(), 1u);
    EXPECT_TRUE(HasWarning(*c, "UnitScaleFactor 100), metres")) << c->warnings[0];
  }
  EXPECT_TRUE(HasWarning(*ParseAsset(AssetFormat::kFbx, ascii, "box"), "up axis +Z"));
}

TEST(FbxImport, DuplicateNodeNamesBecomeUnique) {
  const std::string bytes = Shared("cubes_with_names.fbx");
  if (bytes.empty()) GTEST_SKIP() << "shared data not found";
  auto c = ParseAsset(AssetFormat::kFbx, bytes, "cubes");
  ASSERT_TRUE(c.ok()) << c.status().message();
  const Skeleton& s = *c->skeletons[0].skeleton;
  EXPECT_GE(s.Find("Куб1"), 0);
  EXPECT_GE(s.Find("Куб1_1"), 0);
  EXPECT_EQ(c->meshes.size(), 4u);
}

// tests/data/fbx/pivots.fbx (hand-written ASCII FBX, also a fuzz seed): a node
// translated (0, 1, 0), pre-rotated 90° about X around the pivot (0, 0.5, 0),
// above "mixamorig:Hips" rotated 30° about Z, which holds a triangle. (three.js's
// FBXLoader 0.187 leaves this file's Null parent out and puts the triangle at the
// origin; the values below are FBX's transform formula worked by hand.)

TEST(FbxImport, PivotsAndPreRotationsFoldIntoTheJoint) {
  const auto bytes = ReadFileBytes(fs::path(ARMATURE_TEST_DIR) / "data/fbx/pivots.fbx");
  ASSERT_TRUE(bytes.has_value());
  auto c = ParseAsset(AssetFormat::kFbx, *bytes, "p");
  ASSERT_TRUE(c.ok()) << c.status().message();
  const Skeleton& s = *c->skeletons[0].skeleton;
  ASSERT_EQ(s.size(), 2u);  // no helper nodes: root and the Mixamo-named joint
  EXPECT_EQ(s.names[1], "mixamorig:Hips");
  // By hand, FBX's T·Rp·Rpre·R·Rp⁻¹: (0,1,0) + (0,0.5,0) − Rx(90°)·(0,0.5,0) = (0, 1.5, −0.5).
  EXPECT_TRUE(s.rest[0].translation.isApprox(Eigen::Vector3d(0, 1.5, -0.5), 1e-6)) << s.rest[0].translation.transpose();
  const Eigen::Quaterniond pre(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()));
  EXPECT_NEAR(s.rest[0].rotation.angularDistance(pre), 0, 1e-6);
  const Eigen::Quaterniond z30(Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(s.rest[1].rotation.angularDistance(z30), 0, 1e-6);
  ASSERT_EQ(c->meshes.size(), 1u);
  EXPECT_EQ(c->meshes[0].mesh->joints, std::vector<int>{1});  // rigid on its node
}

TEST(FbxImport, BrokenBytesAreInvalidArgument) {
  for (const std::string bytes :
       {std::string(), std::string("Kaydara FBX Binary  \0\x1a\0", 23),
        std::string("; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n"), std::string("not an fbx at all")}) {
    auto c = ParseAsset(AssetFormat::kFbx, bytes, "x");
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.status().code(), StatusCode::kInvalidArgument) << c.status().message();
    EXPECT_EQ(c.status().message().rfind("FBX", 0), 0u) << c.status().message();
  }
  // Every prefix of a real file fails or imports, never crashes.
  const std::string box = Shared("box.fbx");
  for (size_t n = 0; n < box.size(); n += 997) (void)ParseAsset(AssetFormat::kFbx, box.substr(0, n), "x");
}

// A binary FBX whose first record's lengths run past the file (found by
// engine_compress_fuzz): assimp's tokenizer failed its own check
// `begin <= cursor`, and Debian's libassimp aborted the process on it.
TEST(FbxImport, AFailedAssimpCheckIsAnErrorNotAnAbort) {
  std::string bytes = "Kaydara FBX Binary# a te\no t";
  bytes += std::string(7, '\0') + "\x01hi" + std::string(58, '\xff') + "h\nHI";
  bytes.resize(500, 'x');
  auto c = ParseAsset(AssetFormat::kFbx, bytes, "x");
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.status().code(), StatusCode::kInvalidArgument) << c.status().message();
  EXPECT_EQ(c.status().message(), "FBX: assimp's check begin <= cursor failed (FBXBinaryTokenizer.cpp:136)");
  // The next file reads as before.
  const std::string box = Shared("box.fbx");
  if (!box.empty()) EXPECT_TRUE(ParseAsset(AssetFormat::kFbx, box, "box").ok());
}

TEST(FbxImport, LimitsAreTheOtherFormats) {
  const std::string bytes = Shared("animation_with_skeleton.fbx");
  if (bytes.empty()) GTEST_SKIP() << "shared data not found";
  ImportLimits limits;
  limits.max_mesh_vertices = 1000;
  auto c = ParseAsset(AssetFormat::kFbx, bytes, "arm", {}, limits);
  ASSERT_EQ(c.status().code(), StatusCode::kResourceExhausted);
  EXPECT_NE(c.status().message().find("2464 vertices is over the import limit max_mesh_vertices = 1000"),
            std::string::npos)
      << c.status().message();
  limits = {};
  limits.max_clip_keys = 10;
  c = ParseAsset(AssetFormat::kFbx, bytes, "arm", {}, limits);
  ASSERT_EQ(c.status().code(), StatusCode::kResourceExhausted);
  EXPECT_NE(c.status().message().find("max_clip_keys = 10"), std::string::npos) << c.status().message();
}

// A cycle in the object connections sent assimp's node conversion into
// endless recursion until the stack overflowed (fuzz.engine_fbx_fuzz, from
// pivots.fbx with one connection added; tests/fuzz/regressions keeps it).
TEST(FbxImport, ConnectionCyclesAreRefusedBeforeAssimpFollowsThem) {
  const auto bytes = ReadFileBytes(fs::path(ARMATURE_TEST_DIR) / "data/fbx/pivots.fbx");
  ASSERT_TRUE(bytes.has_value());
  const std::string edge = "C: \"OO\",3000,2000";
  std::string ascii(bytes->begin(), bytes->end());
  const size_t at = ascii.find(edge);
  ASSERT_NE(at, std::string::npos);
  ascii.insert(at + edge.size(), "\n\tC: \"OO\",2000,3000");
  auto refused = ParseAsset(AssetFormat::kFbx, ascii, "p");
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(refused.status().message().find("cycle"), std::string::npos) << refused.status().message();

  // assimp links objects by any connection type but "PP", so a mistyped one
  // closes the cycle too (fuzz.engine_fbx_fuzz), also with its tokens on
  // two lines; a "PP" one is not followed, so it is not a cycle.
  // assimp reads an id token's leading digits and skips the rest, so
  // "2000-0" is 2000 and the next token, 3000, the parent; an id past 2^64
  // that assimp sees overflow is 0 (fuzz.engine_fbx_fuzz).
  for (const std::string closing : {"\n\tC: \"OxglO\",2000,3000", "\n\tC: \"OP\",\n\t\t2000, 3000, \"p\"",
                                    "\n\tC: \"OO\",2000-0\n,3000", "\n\tC: \"OO\",2000x9,3000"}) {
    std::string mistyped(bytes->begin(), bytes->end());
    mistyped.insert(at + edge.size(), closing);
    auto r = ParseAsset(AssetFormat::kFbx, mistyped, "p");
    ASSERT_FALSE(r.ok()) << closing;
    EXPECT_NE(r.status().message().find("cycle"), std::string::npos) << r.status().message();
  }
  std::string property_link(bytes->begin(), bytes->end());
  property_link.insert(at + edge.size(), "\n\tC: \"PP\",2000,\"a\",3000,\"b\"");
  auto kept = ParseAsset(AssetFormat::kFbx, property_link, "p");
  EXPECT_EQ(kept.ok() ? std::string::npos : kept.status().message().find("cycle"), std::string::npos)
      << kept.status().message();

  // The same in a binary file (version 7400: 32-bit record headers): a
  // Connections record holding C records 5 → 6, 6 → 7, 7 → 5.
  auto record = [](const std::string& name, const std::string& props, const std::string& children, size_t at) {
    std::string r(13, '\0');
    const auto put = [&r](size_t i, uint32_t v) { std::memcpy(&r[i], &v, 4); };
    const size_t end = at + 13 + name.size() + props.size() + children.size();
    put(0, static_cast<uint32_t>(end));
    put(8, static_cast<uint32_t>(props.size()));
    r[12] = static_cast<char>(name.size());
    return r + name + props + children;
  };
  auto connection = [](int64_t child, int64_t parent) {
    std::string p = "S";
    const uint32_t two = 2;
    p.append(reinterpret_cast<const char*>(&two), 4).append("OO");
    for (int64_t id : {child, parent}) p.append("L").append(reinterpret_cast<const char*>(&id), 8);
    return p;
  };
  std::string binary("Kaydara FBX Binary  \0\x1a\0", 23);
  const uint32_t version = 7400;
  binary.append(reinterpret_cast<const char*>(&version), 4);
  const size_t connections_at = binary.size();
  std::string children;
  const std::pair<int64_t, int64_t> edges[] = {{5, 6}, {6, 7}, {7, 5}};
  for (const auto& [child, parent] : edges)
    children += record("C", connection(child, parent), "", connections_at + 13 + 11 + children.size());
  children += std::string(13, '\0');  // the null record that ends the list
  binary += record("Connections", "", children, connections_at);
  binary += std::string(13, '\0');
  auto binary_refused = ParseAsset(AssetFormat::kFbx, binary, "b");
  ASSERT_FALSE(binary_refused.ok());
  EXPECT_NE(binary_refused.status().message().find("cycle"), std::string::npos) << binary_refused.status().message();

  // Without the last edge it is a chain: no cycle (assimp then refuses the file for its own reasons).
  std::string chain = binary;
  const std::string last = connection(7, 5), fixed = connection(7, 8);
  chain.replace(chain.find(last), last.size(), fixed);
  auto chained = ParseAsset(AssetFormat::kFbx, chain, "c");
  EXPECT_EQ(chained.ok() ? std::string::npos : chained.status().message().find("cycle"), std::string::npos);
}

// assimp reads scopes and connections recursively: a chain of 10,000
// connected objects or 30,000 nested scopes overflowed an 8 MB stack and
// ended the process. Over 1,000 deep, either is refused before assimp.
TEST(FbxImport, DeepChainsAndScopesAreRefusedBeforeAssimpRecursesThroughThem) {
  auto ascii_chain = [](int models) {
    std::string fbx = "; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n\tFBXVersion: 7400\n}\nObjects:  {\n";
    for (int i = 1; i <= models; ++i)
      fbx += "\tModel: " + std::to_string(i) + ", \"Model::m" + std::to_string(i) + "\", \"Null\" {\n\t}\n";
    fbx += "}\nConnections:  {\n\tC: \"OO\",1,0\n";
    for (int i = 2; i <= models; ++i) fbx += "\tC: \"OO\"," + std::to_string(i) + "," + std::to_string(i - 1) + "\n";
    return fbx + "}\n";
  };
  auto deep = ParseAsset(AssetFormat::kFbx, ascii_chain(20000), "deep");
  ASSERT_FALSE(deep.ok());
  EXPECT_EQ(deep.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(deep.status().message().find("a chain of over 1000 connected objects"), std::string::npos)
      << deep.status().message();
  auto shallow = ParseAsset(AssetFormat::kFbx, ascii_chain(500), "shallow");
  EXPECT_TRUE(shallow.ok()) << shallow.status().message();
  if (shallow.ok()) EXPECT_EQ(shallow->skeletons.at(0).skeleton->size(), 500u);

  std::string braces = "; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n\tFBXVersion: 7400\n}\nFoo:  {\n";
  for (int i = 0; i < 30000; ++i) braces += "a: {";
  braces += std::string(30000, '}') + "\n}\n";
  auto nested = ParseAsset(AssetFormat::kFbx, braces, "n");
  ASSERT_FALSE(nested.ok());
  EXPECT_EQ(nested.status().message(), "FBX: braces nested 30001 deep, over the limit of 1000");

  // The same in a binary file (version 7400): 30,000 records each holding
  // the next, every list ended by a null record.
  constexpr size_t kDepth = 30000, kFirst = 27, kStep = 14;  // a 13-byte header and the name "a"
  std::string binary("Kaydara FBX Binary  \0\x1a\0", 23);
  const uint32_t version = 7400;
  binary.append(reinterpret_cast<const char*>(&version), 4);
  const size_t innermost_end = kFirst + kStep * kDepth;
  for (size_t k = 0; k < kDepth; ++k) {
    std::string header(13, '\0');
    const auto end = static_cast<uint32_t>(innermost_end + 13 * (kDepth - 1 - k));
    std::memcpy(&header[0], &end, 4);
    header[12] = 1;
    binary += header + "a";
  }
  for (size_t k = 0; k + 1 < kDepth; ++k) binary += std::string(13, '\0');
  binary += std::string(13, '\0');
  auto records = ParseAsset(AssetFormat::kFbx, binary, "r");
  ASSERT_FALSE(records.ok());
  EXPECT_EQ(records.status().message(), "FBX: records nested 29999 deep, over the limit of 1000");
}

// assimp keeps the last object of an id and leaks the others, even when the
// import succeeds (found by fuzz.engine_fbx_fuzz), so a repeated id is
// refused, in ASCII and in binary.
TEST(FbxImport, ObjectsSharingAnIdAreRefused) {
  const auto bytes = ReadFileBytes(fs::path(ARMATURE_TEST_DIR) / "data/fbx/pivots.fbx");
  ASSERT_TRUE(bytes.has_value());
  std::string ascii(bytes->begin(), bytes->end());
  const size_t model = ascii.find("Model: 3000,");
  ASSERT_NE(model, std::string::npos);
  ascii.replace(model, 12, "Model: 2000,");
  auto refused = ParseAsset(AssetFormat::kFbx, ascii, "p");
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), StatusCode::kInvalidArgument);
  const size_t line = static_cast<size_t>(std::count(ascii.begin(), ascii.begin() + model, '\n')) + 1;
  EXPECT_NE(refused.status().message().find("two objects share the id 2000"), std::string::npos)
      << refused.status().message();
  EXPECT_NE(refused.status().message().find(" and " + std::to_string(line) + ")"), std::string::npos)
      << refused.status().message();
  // The same id outside the Objects scope (a connection's) is not an object's.
  EXPECT_TRUE(ParseAsset(AssetFormat::kFbx, std::string(bytes->begin(), bytes->end()), "p").ok());

  // box.fbx's objects, read off its Objects record: its Model takes its
  // Geometry's id (both 'L' properties, little-endian).
  std::string box = Shared("box.fbx");
  if (box.empty()) GTEST_SKIP() << "shared data not found";
  auto id_bytes = [](int64_t id) {
    std::string s(1, 'L');
    s.append(reinterpret_cast<const char*>(&id), sizeof id);
    return s;
  };
  const size_t model_id = box.find(id_bytes(2919657087056));
  ASSERT_NE(model_id, std::string::npos);
  box.replace(model_id, 9, id_bytes(2919869934160));
  auto binary = ParseAsset(AssetFormat::kFbx, box, "box");
  ASSERT_FALSE(binary.ok());
  EXPECT_EQ(binary.status().message(),
            "FBX: two objects share the id 2919869934160 (at bytes 11176 and 15234); an object's id must be its own");
}

// assimp inflates a binary file's deflated arrays to the counts they
// declare: a 1.6 MB file of deflated zeros declaring 201 M doubles took
// 2.4 GB in the reader. The declared bytes count against max_decoded_bytes
// before assimp reads anything.
TEST(FbxImport, ArraysThatWouldInflatePastTheLimitAreRefused) {
  // A version 7400 file (32-bit record headers): Objects holding a
  // Geometry holding Vertices, 2^28 doubles (2 GB) from 4 stored bytes.
  auto record = [](const std::string& name, const std::string& props, const std::string& children, size_t at) {
    std::string r(13, '\0');
    const auto put = [&r](size_t i, uint32_t v) { std::memcpy(&r[i], &v, 4); };
    put(0, static_cast<uint32_t>(at + 13 + name.size() + props.size() + children.size()));
    put(4, 1);
    put(8, static_cast<uint32_t>(props.size()));
    r[12] = static_cast<char>(name.size());
    return r + name + props + children;
  };
  std::string array = "d";
  for (uint32_t v : {uint32_t{1} << 28, 1u, 4u}) array.append(reinterpret_cast<const char*>(&v), 4);  // count, deflated
  array += "junk";
  const std::string id = "L" + std::string("\x01\0\0\0\0\0\0\0", 8);
  std::string binary("Kaydara FBX Binary  \0\x1a\0", 23);
  const uint32_t version = 7400;
  binary.append(reinterpret_cast<const char*>(&version), 4);
  const size_t objects_at = binary.size(), geometry_at = objects_at + 13 + 7, vertices_at = geometry_at + 13 + 8 + 9;
  const std::string vertices = record("Vertices", array, "", vertices_at);
  const std::string geometry = record("Geometry", id, vertices + std::string(13, '\0'), geometry_at);
  binary += record("Objects", "", geometry + std::string(13, '\0'), objects_at) + std::string(13, '\0');
  auto refused = ParseAsset(AssetFormat::kFbx, binary, "bomb");
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(refused.status().message(),
            "FBX: 2147483648 bytes of arrays inflated is over the import limit max_decoded_bytes = 1073741824 (the "
            "largest: \"Vertices\" at byte " +
                std::to_string(vertices_at) + ", 2147483648 bytes from 4 stored)");
  // Under the limit, the same file goes on to assimp, which finds the junk.
  ImportLimits roomy;
  roomy.max_decoded_bytes = uint64_t{4} << 30;
  auto read = ParseFbx(binary, "bomb", roomy);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.status().message().find("arrays inflated"), std::string::npos) << read.status().message();

  // A real file's arrays count too: box.fbx's, against a small limit.
  const std::string box = Shared("box.fbx");
  if (box.empty()) GTEST_SKIP() << "shared data not found";
  ImportLimits small;
  small.max_decoded_bytes = 1000;
  auto box_refused = ParseFbx(box, "box", small);
  ASSERT_FALSE(box_refused.ok());
  EXPECT_EQ(box_refused.status().code(), StatusCode::kResourceExhausted);
  EXPECT_NE(box_refused.status().message().find("is over the import limit max_decoded_bytes = 1000"), std::string::npos)
      << box_refused.status().message();
  EXPECT_TRUE(ParseFbx(box, "box").ok());
}

// Nodes named alike get "_N" suffixes in one pass: 16,000 nodes named
// "Hips" (a 1.2 MB file) took 20 s when each looked for its suffix from 1.
TEST(FbxImport, ThousandsOfNodesNamedAlikeGetTheNextSuffixes) {
  constexpr int kModels = 20000;
  std::string fbx = "; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n\tFBXVersion: 7400\n}\nObjects:  {\n";
  for (int i = 1; i <= kModels; ++i) fbx += "\tModel: " + std::to_string(i) + ", \"Model::Hips\", \"Null\" {\n\t}\n";
  fbx += "}\nConnections:  {\n";
  for (int i = 1; i <= kModels; ++i) fbx += "\tC: \"OO\"," + std::to_string(i) + ",0\n";
  auto c = ParseAsset(AssetFormat::kFbx, fbx + "}\n", "alike");
  ASSERT_TRUE(c.ok()) << c.status().message();
  const Skeleton& skeleton = *c->skeletons.at(0).skeleton;
  ASSERT_EQ(skeleton.size(), static_cast<size_t>(kModels));
  std::vector<std::string> names = skeleton.names;
  std::sort(names.begin(), names.end());
  EXPECT_EQ(std::adjacent_find(names.begin(), names.end()), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "Hips"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "Hips_" + std::to_string(kModels - 1)), names.end());
}

}  // namespace
}  // namespace armature
