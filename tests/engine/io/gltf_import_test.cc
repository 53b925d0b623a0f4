// glTF import: structure (nodes, skins, meshes, morph targets, animations,
// names), the three containers (.gltf with data: URIs, .gltf with external
// buffers given as resources, .glb), and bad input, on files built here.
#include <cmath>
#include <cstring>
#include <functional>
#include <random>

#include <gtest/gtest.h>

#include "armature/engine/io/asset.h"
#include "armature/engine/kinematics/fk.h"
#include "armature/engine/math/rotation.h"
#include "armature/engine/mesh/skinning.h"
#include "../testing/exact_clip.h"
#include "../testing/mesh_test_util.h"

namespace armature {
namespace {

using Json = nlohmann::json;

std::string Base64(const std::string& bytes) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = uint8_t(bytes[i]) << 16 | uint8_t(bytes[i + 1]) << 8 | uint8_t(bytes[i + 2]);
    out += {k[v >> 18], k[v >> 12 & 63], k[v >> 6 & 63], k[v & 63]};
  }
  if (i + 1 == bytes.size()) {
    const uint32_t v = uint8_t(bytes[i]) << 16;
    out += {k[v >> 18], k[v >> 12 & 63], '=', '='};
  } else if (i + 2 == bytes.size()) {
    const uint32_t v = uint8_t(bytes[i]) << 16 | uint8_t(bytes[i + 1]) << 8;
    out += {k[v >> 18], k[v >> 12 & 63], k[v >> 6 & 63], '='};
  }
  return out;
}

// Builds a glTF document with one binary buffer.
class Builder {
 public:
  Json json = {{"asset", {{"version", "2.0"}}},
               {"buffers", Json::array()},
               {"bufferViews", Json::array()},
               {"accessors", Json::array()}};
  std::string bin;

  // Appends `values` (as `T`) and an accessor over them; returns its index.
  template <class T>
  int Add(const std::vector<T>& values, const char* type, int component_type, bool normalized = false) {
    while (bin.size() % 4) bin.push_back('\0');
    const size_t offset = bin.size();
    bin.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
    const size_t width = std::string(type) == "SCALAR" ? 1 : std::string(type) == "MAT4" ? 16 : type[3] - '0';
    json["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * sizeof(T)}});
    Json a = {{"bufferView", json["bufferViews"].size() - 1},
              {"componentType", component_type},
              {"count", values.size() / width},
              {"type", type}};
    if (normalized) a["normalized"] = true;
    json["accessors"].push_back(a);
    return static_cast<int>(json["accessors"].size()) - 1;
  }
  int Floats(const std::vector<float>& v, const char* type) { return Add(v, type, 5126); }

  // The document with the buffer as a data: URI, or as an external uri.
  std::string Gltf(const std::string& external_uri = "") const {
    Json j = json;
    if (bin.empty()) return j.dump();
    j["buffers"] = Json::array(
        {{{"byteLength", bin.size()},
          {"uri", external_uri.empty() ? "data:application/octet-stream;base64," + Base64(bin) : external_uri}}});
    return j.dump();
  }
  std::string Glb() const {
    Json j = json;
    j["buffers"] = Json::array({{{"byteLength", bin.size()}}});
    std::string text = j.dump();
    while (text.size() % 4) text.push_back(' ');
    std::string body = bin;
    while (body.size() % 4) body.push_back('\0');
    std::string glb;
    auto u32 = [&](uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
    glb += "glTF";
    u32(2);
    u32(static_cast<uint32_t>(12 + 8 + text.size() + 8 + body.size()));
    u32(static_cast<uint32_t>(text.size()));
    u32(0x4E4F534A);
    glb += text;
    u32(static_cast<uint32_t>(body.size()));
    u32(0x004E4942);
    glb += body;
    return glb;
  }
};

// A 6-joint chain along +Y (node 0 "root" … node 5), a skinned mesh on node 6
// (with a translation glTF says to ignore), an unnamed rigid mesh on node 7
// under joint 2, two animations.
Builder MakeModel() {
  Builder b;
  Json nodes = Json::array();
  for (int i = 0; i < 6; ++i) {
    Json n = {{"name", i == 0 ? "root" : "j" + std::to_string(i)}};
    if (i > 0) n["translation"] = {0, 1, 0};
    if (i < 5) n["children"] = {i + 1};
    nodes.push_back(n);
  }
  nodes[2]["children"] = {3, 7};
  nodes.push_back({{"name", "body"}, {"mesh", 0}, {"skin", 0}, {"translation", {5, 5, 5}}});
  nodes.push_back({{"mesh", 1}, {"translation", {1, 0, 0}}});
  b.json["nodes"] = nodes;
  b.json["scenes"] = {{{"nodes", {0, 6}}}};

  // Skin: inverse bind = translation by −(0, i, 0).
  std::vector<float> ibm;
  for (int i = 0; i < 6; ++i) {
    const float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -float(i), 0, 1};
    ibm.insert(ibm.end(), m, m + 16);
  }
  b.json["skins"] = {{{"joints", {0, 1, 2, 3, 4, 5}}, {"inverseBindMatrices", b.Floats(ibm, "MAT4")}, {"skeleton", 0}}};

  // Four vertices; vertex 3 has six influences over JOINTS_0/JOINTS_1 summing to 0.5.
  const int pos = b.Floats({0, 0.5f, 0, 1, 1.5f, 0, 0, 2.5f, 1, 0, 3, 0}, "VEC3");
  const int nrm = b.Floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  const int idx = b.Add<uint16_t>({0, 1, 2, 0, 2, 3}, "SCALAR", 5123);
  const int j0 = b.Add<uint8_t>({0, 0, 0, 0, 1, 2, 0, 0, 2, 0, 0, 0, 0, 1, 2, 3}, "VEC4", 5121);
  const int w0 = b.Add<uint8_t>({255, 0, 0, 0, 128, 127, 0, 0, 255, 0, 0, 0, 25, 25, 25, 25}, "VEC4", 5121, true);
  const int j1 = b.Add<uint16_t>({0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 4, 5, 0, 0}, "VEC4", 5123);
  const int w1 = b.Floats({0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.1f, 0.1f, 0, 0}, "VEC4");
  // A sparse morph target moving vertex 2 by (0, 0, 1).
  const int sparse_indices = b.Add<uint16_t>({2}, "SCALAR", 5123);
  const int sparse_values = b.Floats({0, 0, 1}, "VEC3");
  Json target = {
      {"componentType", 5126},
      {"count", 4},
      {"type", "VEC3"},
      {"sparse",
       {{"count", 1},
        {"indices", {{"bufferView", b.json["accessors"][sparse_indices]["bufferView"]}, {"componentType", 5123}}},
        {"values", {{"bufferView", b.json["accessors"][sparse_values]["bufferView"]}}}}}};
  b.json["accessors"].push_back(target);
  const int morph = static_cast<int>(b.json["accessors"].size()) - 1;
  b.json["meshes"] = {
      {{"name", "body"},
       {"primitives",
        {{{"attributes",
           {{"POSITION", pos},
            {"NORMAL", nrm},
            {"JOINTS_0", j0},
            {"WEIGHTS_0", w0},
            {"JOINTS_1", j1},
            {"WEIGHTS_1", w1}}},
          {"indices", idx},
          {"targets", {{{"POSITION", morph}}}}}}},
       {"weights", {0.25}},
       {"extras", {{"targetNames", {"raise"}}}}},
      {{"primitives", {{{"attributes", {{"POSITION", b.Floats({0, 0, 0, 1, 0, 0, 0, 0, 1}, "VEC3")}}}}}}}};

  // Animation "wave": joint 1 rotates 90° about Z over 1 s; unnamed: translation STEP on node 7.
  const int t = b.Floats({0, 1}, "SCALAR");
  const float s = std::sqrt(0.5f);
  const int rot = b.Floats({0, 0, 0, 1, 0, 0, s, s}, "VEC4");
  const int tr = b.Floats({1, 0, 0, 2, 0, 0}, "VEC3");
  b.json["animations"] = {{{"name", "wave"},
                           {"channels", {{{"sampler", 0}, {"target", {{"node", 1}, {"path", "rotation"}}}}}},
                           {"samplers", {{{"input", t}, {"output", rot}}}}},
                          {{"channels", {{{"sampler", 0}, {"target", {{"node", 7}, {"path", "translation"}}}}}},
                           {"samplers", {{{"input", t}, {"output", tr}, {"interpolation", "STEP"}}}}}};
  return b;
}

TEST(GltfImport, ImportsNodesSkinsMeshesTargetsAndAnimations) {
  const Builder b = MakeModel();
  auto contents = ParseGltf(b.Gltf(), false, "model");
  ASSERT_TRUE(contents.ok()) << contents.status().message();

  ASSERT_EQ(contents->skeletons.size(), 1u);
  const Skeleton& sk = *contents->skeletons[0].skeleton;
  EXPECT_EQ(contents->skeletons[0].name, "model");
  ASSERT_EQ(sk.size(), 8u);
  EXPECT_EQ(sk.names[0], "root");
  EXPECT_EQ(sk.Find("node7") >= 0, true);  // unnamed nodes are named by index
  for (size_t i = 1; i < sk.size(); ++i) EXPECT_LT(sk.parents[i], static_cast<int>(i));
  EXPECT_EQ(sk.parents[static_cast<size_t>(sk.Find("node7"))], sk.Find("j2"));

  ASSERT_EQ(contents->meshes.size(), 2u);
  EXPECT_EQ(contents->meshes[0].name, "model.body");
  EXPECT_EQ(contents->meshes[0].skeleton_name, "model");
  EXPECT_EQ(contents->meshes[1].name, "model.1");
  const Mesh& body = *contents->meshes[0].mesh;
  EXPECT_EQ(body.vertex_count(), 4u);
  EXPECT_EQ(body.triangle_count(), 2u);
  EXPECT_EQ(body.joints.size(), 6u);
  EXPECT_EQ(body.skeleton_root, sk.Find("root"));
  EXPECT_EQ(body.influence_histogram(), (std::vector<size_t>{0, 2, 1, 0, 0, 0, 1}));
  // Vertex 3: six joints (four at 25/255, two at 0.1) normalized by their sum, and reported.
  const double sum = 4 * 25 / 255.0 + 0.2;
  std::vector<float> expected = {float(0.1 / sum), float(0.1 / sum)};
  for (int i = 0; i < 4; ++i) expected.push_back(float(25 / 255.0 / sum));
  const std::vector<float> actual(body.influence_weights.begin() + body.influence_offsets[3],
                                  body.influence_weights.begin() + body.influence_offsets[4]);
  ASSERT_EQ(actual.size(), 6u);
  for (size_t i = 0; i < 6; ++i) EXPECT_NEAR(actual[i], expected[i], 1e-6);
  ASSERT_FALSE(contents->warnings.empty());
  EXPECT_NE(contents->warnings[0].find("meshes[0]: 1 vertices had weights not summing to 1"), std::string::npos)
      << contents->warnings[0];
  ASSERT_EQ(body.targets.size(), 1u);
  EXPECT_EQ(body.targets[0].name, "raise");
  EXPECT_EQ(body.targets[0].vertices, std::vector<uint32_t>{2});
  EXPECT_EQ(body.default_weights, std::vector<float>{0.25f});

  ASSERT_EQ(contents->clips.size(), 2u);
  EXPECT_EQ(contents->clips[0].name, "model.wave");
  EXPECT_EQ(contents->clips[1].name, "model.1");
  EXPECT_EQ(contents->clips[0].skeleton_name, "model");
  EXPECT_DOUBLE_EQ(contents->clips[0].clip->duration, 1.0);

  // At rest the skin puts vertices where the file has them (plus the default
  // morph), ignoring the skinned node's own translation.
  SkinningWorkspace ws;
  std::vector<float> p(12);
  ASSERT_TRUE(SkinPose(body, sk, sk.rest, {}, p, {}, ws).ok());
  EXPECT_NEAR(p[1], 0.5, 1e-6);
  EXPECT_NEAR(p[8], 1.25, 1e-6);  // vertex 2: z = 1 + 0.25·1
  EXPECT_NEAR(p[10], 3, 1e-6);

  // The rigid mesh follows its node (j2 at y = 2, node at x + 1), STEP-animated.
  const Mesh& rigid = *contents->meshes[1].mesh;
  std::vector<float> q(9);
  ASSERT_TRUE(test_util::SkinExactClip(rigid, *contents->clips[1].clip, 0.5, {}, {}, q, {}, ws).ok());
  EXPECT_NEAR(q[0], 1, 1e-6);
  EXPECT_NEAR(q[1], 2, 1e-6);
  ASSERT_TRUE(test_util::SkinExactClip(rigid, *contents->clips[1].clip, 1.0, {}, {}, q, {}, ws).ok());
  EXPECT_NEAR(q[0], 2, 1e-6);

  // "wave" turns joint 1 by 45° at t = 0.5: vertex 1 (on joint 1) swings about (0, 1, 0).
  ASSERT_TRUE(test_util::SkinExactClip(body, *contents->clips[0].clip, 0.5, {}, {}, p, {}, ws).ok());
  const Eigen::Vector3d v1 = Eigen::Vector3d(0, 1, 0) + AxisRotation(Axis::kZ, M_PI / 4) * Eigen::Vector3d(1, 0.5, 0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(p[3 + c], v1[c], 1e-5);
}

TEST(GltfImport, SeveralSkinsShareOneSkeleton) {
  Builder b = MakeModel();
  // A second skin over joints 3–5 (no inverse bind matrices: identity) on a new node.
  b.json["skins"].push_back({{"joints", {3, 4, 5}}});
  const int pos = b.Floats({0, 0, 0, 0, 1, 0, 0, 0, 1}, "VEC3");
  const int joints = b.Add<uint8_t>({0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0}, "VEC4", 5121);
  const int weights = b.Floats({1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, "VEC4");
  b.json["meshes"].push_back(
      {{"name", "hat"},
       {"primitives", {{{"attributes", {{"POSITION", pos}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}}}}}}});
  b.json["nodes"].push_back({{"name", "hat_node"}, {"mesh", 2}, {"skin", 1}});
  auto contents = ParseGltf(b.Gltf(), false, "model");
  ASSERT_TRUE(contents.ok()) << contents.status().message();
  ASSERT_EQ(contents->skeletons.size(), 1u);
  ASSERT_EQ(contents->meshes.size(), 3u);
  const Skeleton& sk = *contents->skeletons[0].skeleton;
  const Mesh& hat = *contents->meshes[2].mesh;
  EXPECT_EQ(contents->meshes[2].name, "model.hat");
  EXPECT_EQ(contents->meshes[2].skeleton_name, "model");
  EXPECT_EQ(hat.joints, (std::vector<int>{sk.Find("j3"), sk.Find("j4"), sk.Find("j5")}));
  EXPECT_EQ(contents->meshes[0].mesh->joints.size(), 6u);
  // Identity inverse binds: a vertex on j4 (world y = 4) moves by j4's world transform.
  std::vector<float> p(9);
  SkinningWorkspace ws;
  ASSERT_TRUE(SkinPose(hat, sk, sk.rest, {}, p, {}, ws).ok());
  EXPECT_NEAR(p[4], 5, 1e-6);  // (0, 1, 0) + (0, 4, 0)
}

TEST(GltfImport, ExternalBuffersComeFromResourcesAndGlbMatches) {
  const Builder b = MakeModel();
  auto embedded = ParseGltf(b.Gltf(), false, "m");
  ASSERT_TRUE(embedded.ok());
  ResourceMap resources{{"model data.bin", b.bin}};
  auto external = ParseGltf(b.Gltf("model%20data.bin"), false, "m", resources);
  ASSERT_TRUE(external.ok()) << external.status().message();
  auto glb = ParseAsset(AssetFormat::kGlb, b.Glb(), "m");
  ASSERT_TRUE(glb.ok()) << glb.status().message();
  for (const auto* c : {&*external, &*glb}) {
    ASSERT_EQ(c->meshes.size(), 2u);
    EXPECT_EQ(c->meshes[0].mesh->positions, embedded->meshes[0].mesh->positions);
    EXPECT_EQ(c->meshes[0].mesh->influence_weights, embedded->meshes[0].mesh->influence_weights);
    EXPECT_EQ(c->clips.size(), 2u);
  }
  auto missing = ParseAsset(AssetFormat::kGltf, b.Gltf("model.bin"), "m");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(missing.status().message().find("buffer uri 'model.bin' was not provided"), std::string::npos)
      << missing.status().message();
}

TEST(GltfImport, MatrixNodesAreDecomposed) {
  Builder b;
  const Eigen::Quaterniond r = AxisRotation(Axis::kY, 0.7) * AxisRotation(Axis::kX, -0.3);
  Eigen::Affine3d m = Eigen::Translation3d(1, 2, 3) * r * Eigen::Scaling(2.0, 0.5, 1.5);
  Json matrix = Json::array();
  for (int c = 0; c < 4; ++c)
    for (int row = 0; row < 4; ++row) matrix.push_back(m.matrix()(row, c));
  b.json["nodes"] = {{{"name", "a"}, {"matrix", matrix}}};
  auto contents = ParseGltf(b.Gltf(), false, "m");
  ASSERT_TRUE(contents.ok()) << contents.status().message();
  const Trs& rest = contents->skeletons[0].skeleton->rest[0];
  EXPECT_TRUE(rest.ToAffine().matrix().isApprox(m.matrix(), 1e-12));
  EXPECT_TRUE(rest.scale.isApprox(Eigen::Vector3d(2, 0.5, 1.5), 1e-12));
}

struct BadCase {
  const char* name;
  std::function<void(Builder&)> edit;
  const char* expected;
};

class GltfErrors : public ::testing::TestWithParam<BadCase> {};

TEST_P(GltfErrors, NameTheFieldAndAccessor) {
  Builder b = MakeModel();
  GetParam().edit(b);
  auto contents = ParseGltf(b.Gltf(), false, "m");
  ASSERT_FALSE(contents.ok()) << GetParam().name;
  EXPECT_EQ(contents.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(contents.status().message().find(GetParam().expected), std::string::npos) << contents.status().message();
}

Json& Prim(Builder& b) { return b.json["meshes"][0]["primitives"][0]; }

INSTANTIATE_TEST_SUITE_P(
    Cases, GltfErrors,
    ::testing::Values(
        BadCase{"joints_vec3",
                [](Builder& b) { b.json["accessors"][Prim(b)["attributes"]["JOINTS_0"].get<int>()]["type"] = "VEC3"; },
                "meshes[0].primitives[0].attributes.JOINTS_0: accessor 4 has type VEC3, expected VEC4"},
        BadCase{"joints_float", [](Builder& b) { b.json["accessors"][4]["componentType"] = 5126; },
                "attributes.JOINTS_0: accessor 4 has componentType FLOAT, expected UNSIGNED_BYTE or UNSIGNED_SHORT"},
        BadCase{"weights_not_normalized", [](Builder& b) { b.json["accessors"][5].erase("normalized"); },
                "attributes.WEIGHTS_0: accessor 5 has integer componentType UNSIGNED_BYTE but is not normalized"},
        BadCase{"index_out_of_range",
                [](Builder& b) {
                  reinterpret_cast<uint16_t*>(&b.bin[b.json["bufferViews"][3]["byteOffset"].get<size_t>()])[2] = 99;
                },
                "meshes[0].primitives[0].indices: accessor 3 element 2 = 99 is out of range (4 vertices)"},
        BadCase{"joint_out_of_range",
                [](Builder& b) { b.bin[b.json["bufferViews"][4]["byteOffset"].get<size_t>()] = 9; },
                "attributes.JOINTS_0: accessor 4 element 0 uses joint 9 but skin 0 has 6 joints"},
        BadCase{"nan_position",
                [](Builder& b) {
                  const float nan = std::nanf("");
                  std::memcpy(&b.bin[b.json["bufferViews"][1]["byteOffset"].get<size_t>()], &nan, 4);
                },
                "attributes.POSITION: accessor 1 element 0 is not finite"},
        BadCase{"count_beyond_view", [](Builder& b) { b.json["accessors"][1]["count"] = 40; },
                "attributes.POSITION: accessor 1 needs 480 bytes of bufferView 1 but it has 48"},
        BadCase{"view_out_of_range", [](Builder& b) { b.json["accessors"][2]["bufferView"] = 42; },
                "attributes.NORMAL: accessor 2 refers to bufferView 42"},
        BadCase{"accessor_out_of_range", [](Builder& b) { Prim(b)["attributes"]["NORMAL"] = 77; },
                "attributes.NORMAL: accessor 77 does not exist"},
        BadCase{"normal_count", [](Builder& b) { b.json["accessors"][2]["count"] = 3; },
                "attributes.NORMAL: accessor 2 has 3 elements, POSITION has 4"},
        BadCase{"no_position", [](Builder& b) { Prim(b)["attributes"].erase("POSITION"); },
                "meshes[0].primitives[0].attributes has no POSITION"},
        BadCase{"lonely_weights", [](Builder& b) { Prim(b)["attributes"].erase("JOINTS_1"); },
                "attributes.WEIGHTS_1 has no matching JOINTS_1"},
        BadCase{"skin_without_joints_attribute",
                [](Builder& b) {
                  for (const char* a : {"JOINTS_0", "WEIGHTS_0", "JOINTS_1", "WEIGHTS_1"})
                    Prim(b)["attributes"].erase(a);
                },
                "needs JOINTS_0 and WEIGHTS_0"},
        BadCase{"ibm_too_few", [](Builder& b) { b.json["accessors"][0]["count"] = 2; },
                "skins[0].inverseBindMatrices: accessor 0 has 2 matrices for 6 joints"},
        BadCase{"skin_joint_node", [](Builder& b) { b.json["skins"][0]["joints"][3] = 40; },
                "skins[0].joints[3]: node 40 does not exist"},
        BadCase{"two_parents",
                [](Builder& b) {
                  b.json["nodes"][4]["children"] = {5, 3};
                },
                "nodes[4].children: node 3 already has parent node 2"},
        BadCase{"cycle", [](Builder& b) { b.json["nodes"][5]["children"] = {0}; }, "the node hierarchy has a cycle"},
        BadCase{"bad_translation",
                [](Builder& b) {
                  b.json["nodes"][1]["translation"] = {1, 2};
                },
                "nodes[1].translation: expected 3 numbers, got 2"},
        BadCase{"weights_count",
                [](Builder& b) {
                  b.json["meshes"][0]["weights"] = {0.1, 0.2};
                },
                "meshes[0].weights: 2 weights for 1 morph targets"},
        BadCase{"bad_interpolation",
                [](Builder& b) { b.json["animations"][0]["samplers"][0]["interpolation"] = "BEZIER"; },
                "animations[0].samplers[0].interpolation 'BEZIER' is not LINEAR, STEP or CUBICSPLINE"},
        BadCase{
            "cubic_count", [](Builder& b) { b.json["animations"][0]["samplers"][0]["interpolation"] = "CUBICSPLINE"; },
            "animations[0].samplers[0].output: accessor 13 has 2 elements, expected 6 (2 keys × 3 for CUBICSPLINE)"},
        BadCase{"times_decrease",
                [](Builder& b) {
                  const float t = -1;
                  std::memcpy(&b.bin[b.json["bufferViews"][11]["byteOffset"].get<size_t>() + 4], &t, 4);
                },
                "animations[0].samplers[0].input: accessor 12 key 1 time -1.000000 does not increase"},
        BadCase{"channel_node", [](Builder& b) { b.json["animations"][0]["channels"][0]["target"]["node"] = 99; },
                "animations[0].channels[0].target.node: node 99 does not exist"},
        BadCase{"draco",
                [](Builder& b) {
                  b.json["extensionsRequired"] = {"KHR_draco_mesh_compression"};
                  b.json["extensionsUsed"] = {"KHR_draco_mesh_compression"};
                },
                "extensionsRequired: 'KHR_draco_mesh_compression' (compressed geometry) is not supported"},
        BadCase{"rotation_as_vec3",
                [](Builder& b) { b.json["animations"][0]["channels"][0]["target"]["path"] = "scale"; },
                "animations[0].samplers[0].output: accessor 13 has type VEC4, expected VEC3"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(GltfImport, GarbageIsInvalidArgument) {
  for (const std::string text :
       {"{", "{}", "not json at all", "{\"asset\": {\"version\": \"2.0\"}, \"buffers\": [{\"byteLength\": 4}]}"}) {
    auto contents = ParseGltf(text, false, "m");
    ASSERT_FALSE(contents.ok()) << text;
    EXPECT_EQ(contents.status().code(), StatusCode::kInvalidArgument);
  }
  auto glb = ParseGltf(std::string("glTF\x02\0\0\0garbage", 15), true, "m");
  EXPECT_EQ(glb.status().code(), StatusCode::kInvalidArgument);
}

// Random corruptions of a valid file: every one either imports or is
// rejected with INVALID_ARGUMENT; none crashes or reads out of bounds.
TEST(GltfImport, CorruptedFilesNeverCrash) {
  std::mt19937 rng(12345);
  const Builder original = MakeModel();
  const char* fields[] = {"count", "byteOffset", "componentType", "bufferView", "type"};
  const Json values[] = {0, 1, 3, 7, 255, 5121, 5125, 5126, -1, 1 << 30, 4294967295u, "VEC2", "MAT4", "SCALAR"};
  for (int iteration = 0; iteration < 400; ++iteration) {
    Builder b = original;
    for (int e = 0; e < 3; ++e) {
      switch (rng() % 4) {
        case 0: b.bin[rng() % b.bin.size()] = static_cast<char>(rng()); break;
        case 1: {
          Json& a = b.json["accessors"][rng() % b.json["accessors"].size()];
          a[fields[rng() % 5]] = values[rng() % 14];
          break;
        }
        case 2: {
          Json& v = b.json["bufferViews"][rng() % b.json["bufferViews"].size()];
          v[rng() % 2 ? "byteLength" : "byteStride"] = values[rng() % 11];
          break;
        }
        default: {
          Json& n = b.json["nodes"][rng() % b.json["nodes"].size()];
          n["children"] = {static_cast<int>(rng() % 10)};
          break;
        }
      }
    }
    auto contents = ParseGltf(b.Gltf(), false, "m");
    if (!contents.ok()) {
      // Inconsistent files are INVALID_ARGUMENT; huge counts are over an ImportLimits cap.
      EXPECT_TRUE(contents.status().code() == StatusCode::kInvalidArgument ||
                  contents.status().code() == StatusCode::kResourceExhausted)
          << contents.status().message();
      continue;
    }
    // Whatever imported must also skin.
    SkinningWorkspace ws;
    for (const auto& named : contents->meshes) {
      std::vector<float> out(3 * named.mesh->vertex_count());
      const Skeleton& sk = *contents->skeletons[0].skeleton;
      EXPECT_TRUE(SkinPose(*named.mesh, sk, sk.rest, {}, out, {}, ws).ok());
    }
  }
}

TEST(GltfImport, CesiumManFromSharedData) {
  const auto path = test_util::SharedData("gltf/cesium_man.gltf");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared test data not found at " << path;
  auto contents = test_util::LoadGltfFile(path, "cesium");
  ASSERT_TRUE(contents.ok()) << contents.status().message();
  EXPECT_EQ(contents->skeletons[0].skeleton->size(), 22u);
  ASSERT_EQ(contents->meshes.size(), 1u);
  EXPECT_EQ(contents->meshes[0].name, "cesium.Cesium_Man");
  const Mesh& m = *contents->meshes[0].mesh;
  EXPECT_EQ(m.vertex_count(), 3273u);
  EXPECT_EQ(m.joints.size(), 19u);
  EXPECT_LE(m.max_influences(), 4u);
  ASSERT_EQ(contents->clips.size(), 1u);
  EXPECT_EQ(contents->clips[0].name, "cesium.0");
  // 210 vertices have weights summing far from 1 (down to 0.18).
  ASSERT_EQ(contents->warnings.size(), 1u);
  EXPECT_NE(contents->warnings[0].find("210 vertices had weights not summing to 1"), std::string::npos)
      << contents->warnings[0];
}

}  // namespace
}  // namespace armature
