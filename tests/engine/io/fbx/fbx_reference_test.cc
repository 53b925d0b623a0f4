// FBX import against an independent reference: three.js's FBXLoader and
// AnimationMixer (tests/reference/fbx_reference.mjs, run by node) give every
// node's world position and every mesh's skinned world-space vertices at
// several times; the engine's import, sampled and skinned as the server does
// (SampleClip + ComputeWorld: EvaluateClip and ComputeFk; SkinClip/SkinPose:
// SkinMesh), must agree within 1e-4 of the model's size.
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/io/asset.h"
#include "armature/engine/kinematics/fk.h"
#include "armature/engine/mesh/skinning.h"
#include "../../testing/test_files.h"

namespace armature {
namespace {

namespace fs = std::filesystem;
using test_util::ReadFileBytes;
using test_util::RunCommand;
using test_util::SharedData;
using test_util::ThreeJsUnavailable;

// three's node names (PropertyBinding.sanitizeNodeName): whitespace → '_', `[ ] . : /` dropped.
std::string ThreeName(const std::string& name) {
  std::string out;
  for (char c : name) {
    if (c == '[' || c == ']' || c == '.' || c == ':' || c == '/') continue;
    out.push_back(std::isspace(static_cast<unsigned char>(c)) ? '_' : c);
  }
  return out;
}

Eigen::Vector3d At(const nlohmann::json& flat, size_t i) {
  return {flat[3 * i].get<double>(), flat[3 * i + 1].get<double>(), flat[3 * i + 2].get<double>()};
}

struct Case {
  const char* file;  // under ../shared/data, or tests/ when `own`
  int animation;     // -1: the rest pose
  bool own = false;  // a file this project made (tests/data/fbx)
};

class FbxReference : public ::testing::TestWithParam<Case> {};

// For each of our mesh's vertices, the three.js vertex with the same rest
// position (assimp joins identical vertices, three keeps one per polygon
// corner), or empty when some vertex has none.
std::vector<size_t> MatchVertices(const Mesh& mesh, const nlohmann::json& rest, double tolerance) {
  const size_t count = rest.size() / 3;
  std::vector<Eigen::Vector3d> theirs(count);
  for (size_t i = 0; i < count; ++i) theirs[i] = At(rest, i);
  std::vector<size_t> match;
  for (const Eigen::Vector3f& p : mesh.positions) {
    size_t best = count;
    double best_d = tolerance;
    for (size_t i = 0; i < count; ++i)
      if (const double d = (theirs[i] - p.cast<double>()).norm(); d <= best_d) best = i, best_d = d;
    if (best == count) return {};
    match.push_back(best);
  }
  return match;
}

// Each joint's world position (a name three.js also has, once) against
// three's at every time; the largest difference.
double CompareJoints(const Skeleton& skeleton, const std::vector<std::vector<Eigen::Affine3d>>& world,
                     const nlohmann::json& nodes, const std::vector<double>& times, double tolerance,
                     const std::string& file, size_t& joints) {
  std::map<std::string, int> count_of;
  for (const auto& n : skeleton.names) ++count_of[ThreeName(n)];
  double worst_joint = 0;
  for (size_t j = 0; j < skeleton.size(); ++j) {
    const std::string name = ThreeName(skeleton.names[j]);
    if (count_of[name] > 1 || !nodes.contains(name)) continue;  // ambiguous, or a node three drops
    ++joints;
    for (size_t t = 0; t < times.size(); ++t) {
      const auto& p = nodes[name][t];
      // mixamo_walk.fbx's EndSite_* leaves hold a constant Lcl Translation and
      // no curve (checked in the file): a finite place below their parent.
      // three.js 0.187 gives them NaN (null in JSON); the engine's value is
      // the file's, so only its finiteness is checked there.
      if (p[0].is_null() || p[1].is_null() || p[2].is_null()) {
        EXPECT_TRUE(world[t][j].translation().allFinite()) << file << " joint " << skeleton.names[j];
        continue;
      }
      const Eigen::Vector3d theirs(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
      const double d = (world[t][j].translation() - theirs).norm();
      worst_joint = std::max(worst_joint, d);
      EXPECT_LE(d, tolerance) << file << " joint " << skeleton.names[j] << " at t=" << times[t];
    }
  }
  return worst_joint;
}

// The clip's runtime form as the server holds an `exact` import: the
// file's keys, sampled and skinned through the one job. Null on failure.
std::shared_ptr<const CompressedClip> ExactRuntimeOf(std::shared_ptr<const Clip> clip) {
  auto compressed = CompressClip(std::move(clip), ClipPrecision{.exact = true});
  EXPECT_TRUE(compressed.ok()) << compressed.status().message();
  return compressed.ok() ? *compressed : nullptr;
}

// World poses at each time, as EvaluateClip/ComputeFk make them (the rest
// pose without a clip).
std::vector<std::vector<Eigen::Affine3d>> WorldPoses(const Skeleton& skeleton, const CompressedClip* runtime,
                                                     const std::vector<double>& times) {
  std::vector<std::vector<Eigen::Affine3d>> world(times.size(), std::vector<Eigen::Affine3d>(skeleton.size()));
  std::vector<Trs> local(skeleton.size());
  for (size_t t = 0; t < times.size(); ++t) {
    local = skeleton.rest;
    if (runtime)
      EXPECT_TRUE((ClipSamplingJob{runtime, times[t], WrapMode::kClamp, nullptr, local, std::nullopt}.Run().ok()));
    ComputeWorld(skeleton, local, world[t]);
  }
  return world;
}

TEST_P(FbxReference, MatchesThreeJs) {
  const Case c = GetParam();
  const fs::path path = c.own ? fs::path(ARMATURE_TEST_DIR) / "data/fbx" / c.file : SharedData(c.file);
  if (!fs::exists(path)) GTEST_SKIP() << path.string() << " not found";
  if (const std::string why = ThreeJsUnavailable(); !why.empty()) GTEST_SKIP() << why;
  const auto bytes = ReadFileBytes(path);
  ASSERT_TRUE(bytes.has_value());
  auto contents = ParseAsset(AssetFormat::kFbx, *bytes, "model");
  ASSERT_TRUE(contents.ok()) << contents.status().message();
  ASSERT_EQ(contents->skeletons.size(), 1u);
  const Skeleton& skeleton = *contents->skeletons[0].skeleton;
  const Clip* clip = nullptr;
  if (c.animation >= 0) {
    ASSERT_GT(contents->clips.size(), static_cast<size_t>(c.animation));
    clip = contents->clips[static_cast<size_t>(c.animation)].clip.get();
  }
  const std::shared_ptr<const CompressedClip> runtime =
      clip ? ExactRuntimeOf(contents->clips[static_cast<size_t>(c.animation)].clip) : nullptr;
  if (clip) ASSERT_NE(runtime, nullptr);
  std::vector<double> times = {0.0};
  if (clip)
    for (double f : {0.13, 0.37, 0.5, 0.71, 0.96, 1.0}) times.push_back(f * clip->duration);
  std::ostringstream list;
  list.precision(17);
  for (size_t i = 0; i < times.size(); ++i) list << (i ? "," : "") << times[i];
  const std::string script = (fs::path(ARMATURE_TEST_DIR) / "reference/fbx_reference.mjs").string();
  const auto out = RunCommand("node '" + script + "' '" + path.string() + "' " + std::to_string(c.animation) + " " +
                              list.str() + " 2>/dev/null");
  ASSERT_TRUE(out.has_value()) << "the three.js reference failed on " << path.string();
  const auto reference = nlohmann::json::parse(*out);
  if (clip) EXPECT_NEAR(reference["durations"][c.animation].get<double>(), clip->duration, 1e-6);

  const auto world = WorldPoses(skeleton, runtime.get(), times);
  // The model's size: the extent of its joints at the first time.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e30), hi = -lo;
  for (const auto& w : world[0]) lo = lo.cwiseMin(w.translation()), hi = hi.cwiseMax(w.translation());
  for (const auto& m : contents->meshes)
    for (const auto& p : m.mesh->positions) lo = lo.cwiseMin(p.cast<double>()), hi = hi.cwiseMax(p.cast<double>());
  const double size = (hi - lo).norm();
  const double tolerance = 1e-4 * size;

  size_t joints = 0;
  const double worst_joint = CompareJoints(skeleton, world, reference["nodes"], times, tolerance, c.file, joints);
  EXPECT_GT(joints, 0u);

  double worst_vertex = 0;
  size_t compared = 0, over_four = 0;
  SkinningWorkspace workspace;
  for (const auto& named : contents->meshes) {
    const Mesh& mesh = *named.mesh;
    std::vector<float> positions(3 * mesh.vertex_count()), normals;
    const auto skin = [&](size_t t) {
      return runtime ? SkinClip(mesh, *runtime, ClipSkinningTime{times[t], WrapMode::kClamp, std::nullopt, nullptr, {}},
                                {}, positions, normals, workspace)
                     : SkinPose(mesh, skeleton, skeleton.rest, {}, positions, normals, workspace);
    };
    // The three.js mesh with the same rest vertices; of several (copies of
    // one cube), the one placed where ours is at the first time.
    ASSERT_TRUE(skin(0).ok());
    std::vector<size_t> match;
    const nlohmann::json* frames = nullptr;
    double best = 1e300;
    for (const auto& theirs : reference["meshes"]) {
      auto candidate = MatchVertices(mesh, theirs["rest"], 1e-6 * size);
      if (candidate.empty()) continue;
      double d = 0;
      for (size_t v = 0; v < mesh.vertex_count(); ++v)
        d = std::max(d, (Eigen::Vector3d(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]) -
                         At(theirs["frames"][0], candidate[v]))
                            .norm());
      if (d < best) best = d, match = std::move(candidate), frames = &theirs["frames"];
    }
    ASSERT_NE(frames, nullptr) << c.file << ": no three.js mesh has the rest vertices of " << named.name;
    for (size_t t = 0; t < times.size(); ++t) {
      ASSERT_TRUE(skin(t).ok());
      for (size_t v = 0; v < mesh.vertex_count(); ++v) {
        // three's FBXLoader keeps a vertex's 4 heaviest weights without
        // renormalizing; the file's own weights (all of them, summing to 1,
        // as assimp reads them) are right, so those vertices are not compared.
        if (mesh.skinned() && mesh.influence_offsets[v + 1] - mesh.influence_offsets[v] > 4) {
          over_four += t == 0;
          continue;
        }
        const Eigen::Vector3d ours(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
        const double d = (ours - At((*frames)[t], match[v])).norm();
        worst_vertex = std::max(worst_vertex, d);
        ++compared;
        EXPECT_LE(d, tolerance) << c.file << " mesh " << named.name << " vertex " << v << " at t=" << times[t];
        if (d > tolerance) return;
      }
    }
  }
  std::cout << "[ reference ] " << c.file << ": size " << size << ", " << joints << " joints, largest joint error "
            << worst_joint / size << " of size; " << compared << " vertex positions, largest error "
            << worst_vertex / size << " of size (" << over_four << " vertices with over 4 weights not compared)\n";
}

INSTANTIATE_TEST_SUITE_P(SharedFiles, FbxReference,
                         ::testing::Values(Case{"fbx/animation_with_skeleton.fbx", 0},
                                           Case{"fbx/animation_with_skeleton.fbx", -1}, Case{"fbx/box_ascii.fbx", -1},
                                           Case{"fbx/cubes_with_names.fbx", -1}, Case{"fbx/global_settings.fbx", -1}));

// Files this project made: tests/data/fbx/mixamo_walk.fbx (tests/tools/make_mixamo_fbx.cc:
// CMU 01_01's first 30 frames, mixamorig: names, written by assimp's FBX exporter).
INSTANTIATE_TEST_SUITE_P(OwnFiles, FbxReference, ::testing::Values(Case{"mixamo_walk.fbx", 0, true}));

}  // namespace
}  // namespace armature
