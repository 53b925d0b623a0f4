// Skinned and morphed glTF models against an independent reference: three.js
// (GLTFLoader + AnimationMixer, run by node on tests/reference/) gives every
// mesh's world-space vertices at several times; the engine must agree within
// 1e-4 of the model's size.
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <algorithm>
#include <iostream>
#include <sstream>

#include <gtest/gtest.h>

#include "armature/engine/io/demo_character.h"
#include "armature/engine/io/gltf/gltf_writer.h"
#include "armature/engine/mesh/skinning.h"
#include "../testing/exact_clip.h"
#include "../testing/mesh_test_util.h"

namespace armature {
namespace {

namespace fs = std::filesystem;
using test_util::LoadGltfFile;
using test_util::RunCommand;
using test_util::SharedData;
using test_util::ThreeJsUnavailable;

// Skins every mesh of `contents` (imported from `path`) with its animation
// `animation` (-1: the rest pose) at times across the clip, and expects
// three.js's world-space vertices within 1e-4 of the model's size.
void ExpectMatchesThreeJs(const fs::path& path, const AssetContents& contents, int animation) {
  ASSERT_FALSE(contents.meshes.empty());
  const Clip* clip = nullptr;
  if (animation >= 0) {
    ASSERT_GT(contents.clips.size(), static_cast<size_t>(animation));
    clip = contents.clips[static_cast<size_t>(animation)].clip.get();
  }
  // Times inside and at the ends of the clip, mostly between keys.
  const double duration = clip ? clip->duration : 0;
  std::vector<double> times;
  for (double f : {0.0, 0.13, 0.37, 0.5, 0.71, 0.96, 1.0}) times.push_back(f * duration);
  std::ostringstream list;
  list.precision(17);
  for (size_t i = 0; i < times.size(); ++i) list << (i ? "," : "") << times[i];

  const std::string script = (fs::path(ARMATURE_TEST_DIR) / "reference/gltf_skin_reference.mjs").string();
  auto out =
      RunCommand("node '" + script + "' '" + path.string() + "' " + std::to_string(animation) + " " + list.str());
  ASSERT_TRUE(out.has_value()) << "the three.js reference failed";
  const auto reference = nlohmann::json::parse(*out);

  SkinningWorkspace workspace;
  const SkinningOptions options;
  const SampleOptions sample;
  for (const auto& ref_mesh : reference["meshes"]) {
    const size_t m = ref_mesh["mesh"];
    ASSERT_LT(m, contents.meshes.size());
    const Mesh& mesh = *contents.meshes[m].mesh;
    const size_t n = mesh.vertex_count();
    std::vector<float> positions(3 * n), normals(mesh.normals.empty() ? 0 : 3 * n);

    // The model's size: the diagonal of the reference's first frame.
    const auto& first = ref_mesh["frames"][0]["positions"];
    ASSERT_EQ(first.size(), 3 * n) << "vertex count differs from three.js for mesh " << m;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e30), hi = -lo;
    for (size_t v = 0; v < n; ++v) {
      const Eigen::Vector3d p(first[3 * v].get<double>(), first[3 * v + 1].get<double>(),
                              first[3 * v + 2].get<double>());
      lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    }
    const double size = (hi - lo).norm();

    double worst_position = 0, worst_normal = 0;
    for (const auto& frame : ref_mesh["frames"]) {
      const double t = frame["time"];
      if (clip) {
        ASSERT_TRUE(test_util::SkinExactClip(mesh, *clip, t, sample, options, positions, normals, workspace).ok());
      } else {
        const Skeleton& skeleton = *contents.skeletons[0].skeleton;
        ASSERT_TRUE(SkinPose(mesh, skeleton, skeleton.rest, options, positions, normals, workspace).ok());
      }
      const auto& p = frame["positions"];
      for (size_t i = 0; i < 3 * n; ++i)
        worst_position = std::max(worst_position, std::abs(positions[i] - p[i].get<double>()));
      const auto& nr = frame["normals"];
      if (!normals.empty() && nr.size() == 3 * n)
        for (size_t i = 0; i < 3 * n; ++i)
          worst_normal = std::max(worst_normal, std::abs(normals[i] - nr[i].get<double>()));
    }
    std::cout << "[ reference ] " << path.filename().string() << " mesh " << m << " (" << n << " vertices, size "
              << size << "): max position error " << worst_position << " (" << worst_position / size
              << " of size), max normal error " << worst_normal << "\n";
    EXPECT_LE(worst_position, 1e-4 * size) << path.filename().string() << " mesh " << m;
    EXPECT_LE(worst_normal, 1e-3) << path.filename().string() << " mesh " << m;
  }
}

struct Case {
  const char* file;
  int animation;  // -1: rest pose
};

class GltfReference : public ::testing::TestWithParam<Case> {};

TEST_P(GltfReference, MatchesThreeJs) {
  if (!fs::exists(SharedData("gltf"))) GTEST_SKIP() << "shared test data not found at " << SharedData("gltf").string();
  if (const std::string why = ThreeJsUnavailable(); !why.empty()) GTEST_SKIP() << why;
  const Case c = GetParam();
  const fs::path path = SharedData(std::string("gltf/") + c.file);
  auto contents = LoadGltfFile(path, "model");
  ASSERT_TRUE(contents.ok()) << contents.status().message();
  ExpectMatchesThreeJs(path, *contents, c.animation);
}

// The project's own demo character (made here, so it needs no shared data):
// its walk and its bind (rest) pose.
TEST(GltfReferenceDemoCharacter, MatchesThreeJs) {
  if (const std::string why = ThreeJsUnavailable(); !why.empty()) GTEST_SKIP() << why;
  auto glb = MakeDemoCharacterGlb();
  ASSERT_TRUE(glb.ok()) << glb.status().message();
  const fs::path path = fs::temp_directory_path() / ("armature_demo_character_" + std::to_string(getpid()) + ".glb");
  std::ofstream(path, std::ios::binary) << *glb;
  auto contents = LoadGltfFile(path, "demo_character");
  ASSERT_TRUE(contents.ok()) << contents.status().message();
  ExpectMatchesThreeJs(path, *contents, 0);
  ExpectMatchesThreeJs(path, *contents, -1);
  fs::remove(path);
}

// What three.js's GLTFLoader builds for `path`'s meshes: materials, maps
// (their image bytes' sha256), UVs (gltf_material_reference.mjs).
nlohmann::json ThreeJsMaterials(const fs::path& path) {
  const std::string script = (fs::path(ARMATURE_TEST_DIR) / "reference/gltf_material_reference.mjs").string();
  auto out = RunCommand("node '" + script + "' '" + path.string() + "'");
  EXPECT_TRUE(out.has_value()) << "the three.js material reference failed on " << path;
  return out ? nlohmann::json::parse(*out) : nlohmann::json();
}

// Exported as GLB and as .gltf, CesiumMan and the robot load in GLTFLoader
// with the material, UVs and image (the same bytes) of the original file.
TEST(GltfReferenceMaterials, ExportMatchesTheOriginalInThreeJs) {
  if (const std::string why = ThreeJsUnavailable(); !why.empty()) GTEST_SKIP() << why;
  for (const char* file : {"cesium_man.gltf", "RobotExpressive/RobotExpressive.glb"}) {
    const fs::path path = SharedData(std::string("gltf/") + file);
    if (!fs::exists(path)) GTEST_SKIP() << "shared data " << path.string() << " is absent";
    auto contents = LoadGltfFile(path, "model");
    ASSERT_TRUE(contents.ok()) << contents.status().message();
    std::vector<const Mesh*> meshes;
    for (const NamedMesh& m : contents->meshes) meshes.push_back(m.mesh.get());
    const nlohmann::json original = ThreeJsMaterials(path);
    ASSERT_FALSE(original["meshes"].empty());
    for (bool binary : {true, false}) {
      auto bytes = ExportGltf(*contents->clips.at(0).clip, meshes, {.binary = binary});
      ASSERT_TRUE(bytes.ok()) << bytes.status().message();
      const fs::path out =
          fs::temp_directory_path() / ("armature_material_" + std::to_string(getpid()) + (binary ? ".glb" : ".gltf"));
      std::ofstream(out, std::ios::binary) << *bytes;
      const nlohmann::json exported = ThreeJsMaterials(out);
      fs::remove(out);
      // Each drawn mesh's material and UVs, sorted: the export places meshes
      // on other nodes, which three.js visits (and names) in another order.
      auto drawn = [](const nlohmann::json& reference) {
        std::vector<std::string> out;
        for (const auto& m : reference["meshes"]) out.push_back(nlohmann::json{m["material"], m["uvs"]}.dump());
        std::sort(out.begin(), out.end());
        return out;
      };
      EXPECT_EQ(drawn(exported), drawn(original)) << file << (binary ? " as GLB" : " as .gltf");
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Models, GltfReference,
                         ::testing::Values(Case{"cesium_man.gltf", 0}, Case{"rigged_simple.gltf", 0},
                                           Case{"simple_skin.gltf", 0},
                                           Case{"AnimatedMorphCube/AnimatedMorphCube.gltf", 0},
                                           Case{"SimpleMorph/SimpleMorph.gltf", 0}, Case{"interpolation_test.gltf", 0},
                                           Case{"interpolation_test.gltf", 2}, Case{"interpolation_test.gltf", 4},
                                           Case{"interpolation_test.gltf", 7}, Case{"cesium_man.gltf", -1}),
                         [](const auto& info) {
                           std::string s = info.param.file;
                           s = s.substr(s.rfind('/') + 1);
                           s = s.substr(0, s.find('.')) + "_anim" + std::to_string(info.param.animation + 1);
                           return s;
                         });

}  // namespace
}  // namespace armature
