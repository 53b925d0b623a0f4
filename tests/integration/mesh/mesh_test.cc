// MeshService end to end: a real armature-server skins the shared glTF models
// and its numbers are compared with the engine's own SkinClip on the same
// file parsed in this process (the engine is checked against three.js in the
// engine tests). Also the CLI's `skin --json`, the REST gateway, bad input
// and the mesh vertex limit.
#include <cmath>
#include <limits>
#include <map>
#include <vector>

// The engine (Eigen) before httplib.h, whose system headers define a macro
// that breaks Eigen's product kernels.
#include "armature/engine/io/asset.h"
#include "armature/engine/mesh/mesh.h"
#include "armature/engine/mesh/skinning.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "engine/testing/mesh_test_util.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "support/client_helpers.h"

namespace armature::testing {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// Expects `call` to fail with `code` and a message naming `field`.
void ExpectStatus(const std::function<void()>& call, grpc::StatusCode code, const std::string& field) {
  const grpc::Status status = StatusOf(call);
  EXPECT_EQ(status.error_code(), code) << field;
  EXPECT_NE(status.error_message().find(field), std::string::npos) << status.error_message();
}

// A glTF file and its buffers, parsed in this process as the server parses it,
// its first clip compressed as the server does at the default bound.
struct Reference {
  AssetContents contents;
  std::shared_ptr<const CompressedClip> runtime;
  static Reference Parse(const fs::path& gltf, const std::string& name) {
    auto parsed = test_util::LoadGltfFile(gltf, name);
    EXPECT_TRUE(parsed.ok()) << parsed.status().message();
    auto runtime = CompressClip(parsed->clips.at(0).clip);
    EXPECT_TRUE(runtime.ok()) << runtime.status().message();
    return {std::move(*parsed), *runtime};
  }
  // Positions and normals the engine gives for mesh 0 by clip 0 at `time`.
  std::pair<std::vector<float>, std::vector<float>> Skin(double time, SkinningMethod method) const {
    const Mesh& mesh = *contents.meshes.at(0).mesh;
    std::vector<float> positions(3 * mesh.vertex_count()), normals(mesh.normals.empty() ? 0 : positions.size());
    SkinningOptions options;
    options.method = method;
    SkinningWorkspace ws;
    const Status st = SkinClip(mesh, *runtime, {time}, options, positions, normals, ws);
    EXPECT_TRUE(st.ok()) << st.message();
    return {positions, normals};
  }
};

template <class Values>
double MaxAbsDifference(const Values& a, const std::vector<float>& b) {
  EXPECT_EQ(static_cast<size_t>(a.size()), b.size());
  double d = 0;
  for (size_t i = 0; i < b.size() && i < static_cast<size_t>(a.size()); ++i)
    d = std::max(d, std::abs(static_cast<double>(a[static_cast<int>(i)]) - b[i]));
  return d;
}

class Meshes : public ::testing::Test {
 protected:
  void SetUp() override {
    if (SharedData("gltf/cesium_man.gltf").empty()) GTEST_SKIP() << "shared glTF data not found (ARMATURE_SHARED_DATA)";
  }
};

// The server's CesiumMan against the same file parsed and skinned in this process.
struct CesiumMan {
  client::Client& client;
  const Reference& ref;
  const Mesh& engine_mesh;
  std::string mesh, clip;
};

// Details and geometry: the rest mesh exactly as parsed, for clients that draw it.
void ExpectDetailsAndGeometry(const CesiumMan& cm, v1::MeshInfo* info_out) {
  client::Client& client = cm.client;
  const Mesh& engine_mesh = cm.engine_mesh;
  const std::string& mesh = cm.mesh;
  const v1::MeshInfo info = client.GetMesh(mesh);
  EXPECT_EQ(info.vertex_count(), static_cast<int>(engine_mesh.vertex_count()));
  EXPECT_GT(info.vertex_count(), 3000);
  EXPECT_EQ(info.triangle_count(), static_cast<int>(engine_mesh.triangle_count()));
  EXPECT_EQ(info.max_influences(), 4);
  EXPECT_EQ(info.skeleton(), "cesium_man");
  const auto list = client.ListMeshes();
  ASSERT_EQ(list.meshes_size(), 1);
  EXPECT_EQ(list.meshes(0).vertex_count(), info.vertex_count());

  const v1::MeshGeometry geometry = client.GetMeshGeometry(mesh);
  ASSERT_EQ(geometry.positions_size(), 3 * info.vertex_count());
  ASSERT_EQ(geometry.normals_size(), 3 * info.vertex_count());
  ASSERT_EQ(geometry.triangles_size(), 3 * info.triangle_count());
  for (size_t v = 0; v < engine_mesh.vertex_count(); ++v)
    for (int c = 0; c < 3; ++c) {
      ASSERT_EQ(geometry.positions(static_cast<int>(3 * v) + c), engine_mesh.positions[v][c]) << v;
      ASSERT_EQ(geometry.normals(static_cast<int>(3 * v) + c), engine_mesh.normals[v][c]) << v;
    }
  for (size_t i = 0; i < engine_mesh.triangles.size(); ++i)
    ASSERT_EQ(geometry.triangles(static_cast<int>(i)), engine_mesh.triangles[i]) << i;
  EXPECT_EQ(CodeOf([&] { client.GetMeshGeometry("nope"); }), grpc::StatusCode::NOT_FOUND);

  *info_out = info;
}

// SkinMesh by clip and time, LBS and DQS, equals the engine's result.
void ExpectSkinningAtTimes(const CesiumMan& cm, double duration) {
  client::Client& client = cm.client;
  const Reference& ref = cm.ref;
  const Mesh& engine_mesh = cm.engine_mesh;
  const std::string &mesh = cm.mesh, &clip = cm.clip;
  ASSERT_GT(duration, 1);
  for (double t : {0.0, 0.37, 1.0, duration * 0.8, duration}) {
    for (auto [method, engine_method] :
         {std::pair{v1::LBS, SkinningMethod::kLinear}, std::pair{v1::DQS, SkinningMethod::kDualQuaternion}}) {
      v1::SkinMeshRequest request;
      request.set_mesh(mesh);
      request.set_clip(clip);
      request.set_time(t);
      request.set_method(method);
      const auto got = client.SkinMesh(request);
      const auto [positions, normals] = ref.Skin(t, engine_method);
      EXPECT_EQ(got.vertex_count(), static_cast<int>(engine_mesh.vertex_count()));
      // The same code on the same floats: equal up to float rounding
      // (the server splits the work across threads as the engine does).
      EXPECT_LE(MaxAbsDifference(got.positions(), positions), 1e-5) << "t=" << t << " method=" << method;
      EXPECT_LE(MaxAbsDifference(got.normals(), normals), 1e-5) << "t=" << t << " method=" << method;
    }
  }
}

// Bad input names the field.
void ExpectBadSkinRequestsNamed(client::Client& client, const v1::SkinMeshRequest& request,
                                const v1::SkinMeshRequest& by_pose) {
  auto call = [&](v1::SkinMeshRequest r) { return [&client, r] { client.SkinMesh(r); }; };
  v1::SkinMeshRequest bad = request;
  bad.set_mesh("nope");
  ExpectStatus(call(bad), grpc::StatusCode::NOT_FOUND, "mesh");
  bad = request;
  bad.set_clip("nope");
  ExpectStatus(call(bad), grpc::StatusCode::NOT_FOUND, "clip");
  bad = request;
  bad.set_time(std::numeric_limits<double>::quiet_NaN());
  ExpectStatus(call(bad), grpc::StatusCode::INVALID_ARGUMENT, "time");
  bad = request;
  bad.set_time(-1);
  EXPECT_EQ(CodeOf(call(bad)), grpc::StatusCode::INVALID_ARGUMENT);
  bad = by_pose;
  bad.mutable_pose()->mutable_rotations()->RemoveLast();
  ExpectStatus(call(bad), grpc::StatusCode::INVALID_ARGUMENT, "pose");
  bad = request;
  bad.add_morph_weights(1);
  ExpectStatus(call(bad), grpc::StatusCode::INVALID_ARGUMENT, "morph_weights");
  bad = request;
  bad.set_method(static_cast<v1::SkinningMethod>(7));
  ExpectStatus(call(bad), grpc::StatusCode::INVALID_ARGUMENT, "method");
  bad = request;
  bad.clear_clip();
  EXPECT_EQ(CodeOf(call(bad)), grpc::StatusCode::INVALID_ARGUMENT);
}

// A stream: frames at the requested pacing, each equal to SkinMesh at its time.
void ExpectSkinnedStream(const CesiumMan& cm) {
  client::Client& client = cm.client;
  const Reference& ref = cm.ref;
  const std::string &mesh = cm.mesh, &clip = cm.clip;
  v1::StreamSkinnedMeshRequest stream;
  stream.set_mesh(mesh);
  stream.set_clip(clip);
  stream.set_fps(60);
  stream.set_duration(0.1);
  int frames = 0;
  client.StreamSkinnedMesh(stream, [&](const v1::SkinnedMeshFrame& frame) {
    EXPECT_EQ(frame.index(), static_cast<uint64_t>(frames));
    EXPECT_NEAR(frame.time(), frames / 60.0, 1e-9);
    const auto [positions, normals] = ref.Skin(frame.time(), SkinningMethod::kLinear);
    EXPECT_LE(MaxAbsDifference(frame.positions(), positions), 1e-5);
    ++frames;
    return true;
  });
  EXPECT_EQ(frames, 6);
}

TEST_F(Meshes, CesiumManSkinnedByTheServerEqualsTheEngine) {
  const fs::path file = SharedData("gltf/cesium_man.gltf");
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  const auto imported = client.ImportFile(file, "cesium_man");
  ASSERT_EQ(imported.asset().meshes_size(), 1);
  ASSERT_GE(imported.asset().clips_size(), 1);
  const std::string mesh = imported.asset().meshes(0).name();
  const std::string clip = imported.asset().clips(0).name();
  const Reference ref = Reference::Parse(file, "cesium_man");
  const Mesh& engine_mesh = *ref.contents.meshes.at(0).mesh;
  ASSERT_EQ(ref.contents.meshes[0].name, mesh);

  const CesiumMan cm{client, ref, engine_mesh, mesh, clip};
  v1::MeshInfo info;
  ExpectDetailsAndGeometry(cm, &info);
  if (HasFatalFailure()) return;
  const double duration = imported.asset().clips(0).duration();
  ExpectSkinningAtTimes(cm, duration);
  if (HasFatalFailure()) return;

  // DQS and LBS differ where joints bend.
  v1::SkinMeshRequest request;
  request.set_mesh(mesh);
  request.set_clip(clip);
  request.set_time(0.5);
  request.set_method(v1::LBS);
  const auto lbs = client.SkinMesh(request);
  request.set_method(v1::DQS);
  const auto dqs = client.SkinMesh(request);
  std::vector<float> lbs_positions(lbs.positions().begin(), lbs.positions().end());
  const double lbs_dqs = MaxAbsDifference(dqs.positions(), lbs_positions);
  EXPECT_GT(lbs_dqs, 1e-4);
  std::printf("cesium_man at 0.5 s: max |DQS - LBS| = %.6g\n", lbs_dqs);

  // A client pose: the clip's local pose at 0.5 s, fetched with EvaluateClip.
  v1::EvaluateClipRequest evaluate;
  evaluate.set_clip(clip);
  evaluate.add_times(0.5);
  evaluate.set_space(v1::LOCAL);
  const auto pose = client.EvaluateClip(evaluate);
  v1::SkinMeshRequest by_pose;
  by_pose.set_mesh(mesh);
  by_pose.set_method(v1::LBS);
  *by_pose.mutable_pose()->mutable_rotations() = pose.poses(0).rotations();
  *by_pose.mutable_pose()->mutable_translations() = pose.poses(0).translations();
  ASSERT_EQ(pose.joints_size(), static_cast<int>(ref.contents.clips[0].clip->skeleton->size()));
  const auto posed = client.SkinMesh(by_pose);
  // Poses travel as floats: close to the clip's result, not bit-equal.
  EXPECT_LE(MaxAbsDifference(posed.positions(), lbs_positions), 1e-4);

  ExpectBadSkinRequestsNamed(client, request, by_pose);
  if (HasFatalFailure()) return;

  // The REST gateway serves the same call.
  httplib::Client http("127.0.0.1", server.http_port());
  http.set_read_timeout(60);
  const auto r = http.Post("/v1/meshes/" + mesh + ":skin",
                           json{{"clip", clip}, {"time", 0.5}, {"method", "DQS"}}.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json body = json::parse(r->body);
  EXPECT_EQ(body["vertexCount"].get<int>(), info.vertex_count());
  const std::vector<float> rest_positions = body["positions"].get<std::vector<float>>();
  EXPECT_EQ(MaxAbsDifference(dqs.positions(), rest_positions), 0.0);
  const auto got_info = http.Get("/v1/meshes/" + mesh);
  ASSERT_TRUE(got_info);
  ASSERT_EQ(got_info->status, 200) << got_info->body;
  EXPECT_EQ(json::parse(got_info->body)["vertexCount"].get<int>(), info.vertex_count());

  ExpectSkinnedStream(cm);
}

// Morph-only meshes through the CLI: the clip's weights track drives the
// morph; the JSON equals the engine's result and differs from the rest shape.
TEST_F(Meshes, MorphTargetsAnimatedByTheClipThroughTheCli) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  for (const std::string relative :
       {"gltf/AnimatedMorphCube/AnimatedMorphCube.gltf", "gltf/SimpleMorph/SimpleMorph.gltf"}) {
    const fs::path file = SharedData(relative);
    if (file.empty()) GTEST_SKIP() << relative << " not found";
    const std::string name = file.stem().string();
    const auto imported = client.ImportFile(file, name);
    ASSERT_EQ(imported.asset().meshes_size(), 1);
    ASSERT_GE(imported.asset().clips_size(), 1);
    const std::string mesh = imported.asset().meshes(0).name();
    const std::string clip = imported.asset().clips(0).name();
    EXPECT_GE(client.GetMesh(mesh).target_names_size(), 2) << mesh;
    const Reference ref = Reference::Parse(file, name);
    const Mesh& engine_mesh = *ref.contents.meshes.at(0).mesh;
    const double duration = imported.asset().clips(0).duration();
    const std::vector<float> first = ref.Skin(0, SkinningMethod::kLinear).first;
    for (double t : {duration * 0.25, duration * 0.5}) {
      const auto cli = RunCli(server.target(), {"skin", mesh, "--clip", clip, "--time", std::to_string(t), "--json"});
      ASSERT_EQ(cli.exit_code, 0) << cli.err;
      const json j = json::parse(cli.out);
      EXPECT_EQ(j["mesh"], mesh);
      EXPECT_EQ(j["vertexCount"].get<size_t>(), engine_mesh.vertex_count());
      const auto positions = j["positions"].get<std::vector<float>>();
      const auto [expected, normals] = ref.Skin(std::stod(std::to_string(t)), SkinningMethod::kLinear);
      EXPECT_LE(MaxAbsDifference(positions, expected), 1e-6) << mesh << " t=" << t;
      EXPECT_LE(MaxAbsDifference(j["normals"].get<std::vector<float>>(), normals), 1e-6) << mesh << " t=" << t;
      // The morph moved something: some vertex is away from its rest place.
      const double moved = MaxAbsDifference(positions, first);
      std::printf("%s at %.3f s: max displacement from t=0 %.6g\n", mesh.c_str(), t, moved);
      EXPECT_GT(moved, 1e-3) << mesh << " t=" << t;
    }
    // Blendshapes alone: all weights 1 on the first target = rest + its deltas.
    v1::EvaluateBlendshapesRequest blend;
    blend.set_mesh(mesh);
    for (size_t i = 0; i < engine_mesh.targets.size(); ++i) blend.add_weights(i == 0 ? 1.f : 0.f);
    const auto shaped = client.EvaluateBlendshapes(blend);
    std::vector<float> expected(3 * engine_mesh.vertex_count());
    for (size_t v = 0; v < engine_mesh.vertex_count(); ++v)
      for (int c = 0; c < 3; ++c) expected[3 * v + c] = engine_mesh.positions[v][c];
    const MorphTarget& target = engine_mesh.targets[0];
    for (size_t k = 0; k < target.vertices.size(); ++k)
      for (int c = 0; c < 3; ++c) expected[3 * target.vertices[k] + c] += target.position_deltas[k][c];
    EXPECT_LE(MaxAbsDifference(shaped.positions(), expected), 1e-6) << mesh;
    blend.add_weights(0);
    EXPECT_EQ(CodeOf([&] { client.EvaluateBlendshapes(blend); }), grpc::StatusCode::INVALID_ARGUMENT);
  }
}

TEST_F(Meshes, MeshVertexLimitRefusesTheImport) {
  const fs::path file = SharedData("gltf/rigged_simple.gltf");
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-mesh-vertices", "100"});
  client::Client client(OptionsFor(server));
  auto import = [&] { client.ImportFile(file, "rigged_simple"); };
  const grpc::Status status = StatusOf(import);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  const std::string& message = status.error_message();
  EXPECT_NE(message.find("--max-mesh-vertices"), std::string::npos) << message;
  EXPECT_NE(message.find("160 vertices"), std::string::npos) << message;
  EXPECT_EQ(client.ListMeshes().meshes_size(), 0);
}

TEST_F(Meshes, BindComputesWeightsForASkeleton) {
  const fs::path file = SharedData("gltf/rigged_simple.gltf");
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  const auto imported = client.ImportFile(file, "rigged_simple");
  ASSERT_EQ(imported.asset().meshes_size(), 1);
  ASSERT_EQ(imported.asset().skeletons_size(), 1);
  v1::BindMeshRequest bind;
  bind.set_mesh(imported.asset().meshes(0).name());
  bind.set_skeleton(imported.asset().skeletons(0).name());
  bind.set_method(v1::DISTANCE);
  bind.set_max_influences(2);
  const auto bound = client.BindMesh(bind);
  const int vertices = imported.asset().meshes(0).vertex_count();
  ASSERT_EQ(bound.influence_offsets_size(), vertices + 1);
  EXPECT_LE(bound.max_influences(), 2);
  const int joints = imported.asset().skeletons(0).joint_count();
  for (int v = 0; v < vertices; ++v) {
    double sum = 0;
    for (uint32_t i = bound.influence_offsets(v); i < bound.influence_offsets(v + 1); ++i) {
      sum += bound.influence_weights(static_cast<int>(i));
      EXPECT_GE(bound.influence_joints(static_cast<int>(i)), 0);
      EXPECT_LT(bound.influence_joints(static_cast<int>(i)), joints);
    }
    EXPECT_NEAR(sum, 1, 1e-5) << "vertex " << v;
  }
  bind.set_max_influences(9);
  EXPECT_NE(MessageOf([&] { client.BindMesh(bind); }).find("max_influences"), std::string::npos);
  bind.set_skeleton("nope");
  EXPECT_EQ(CodeOf([&] { client.BindMesh(bind); }), grpc::StatusCode::NOT_FOUND);
}

}  // namespace
}  // namespace armature::testing
