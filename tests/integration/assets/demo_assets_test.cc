// What a fresh data dir is seeded with: the demo walk clip and the demo
// character, a skinned mesh with a walk clip of its own skeleton, ready for
// the viewer's mesh mode; replicas seeding one new data dir together keep
// one copy of each.
#include <cmath>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "armature/engine/io/demo_walk.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

// Mean of every third float from `first`: the mean x, y or z of packed positions.
double Mean(const google::protobuf::RepeatedField<float>& xyz, int first) {
  double sum = 0;
  for (int i = first; i < xyz.size(); i += 3) sum += xyz[i];
  return sum / (xyz.size() / 3);
}

TEST(DemoAssets, AFreshServerServesAWalkingCharacter) {
  TempDir data;
  ServerProcess server(data.path());
  client::Client client(OptionsFor(server));
  EXPECT_EQ(AssetNames(client), (std::set<std::string>{"demo_character", "demo_walk"}));

  // The mesh, listed with its skeleton.
  const auto meshes = client.ListMeshes();
  ASSERT_EQ(meshes.meshes_size(), 1);
  const v1::MeshInfo& mesh = meshes.meshes(0);
  EXPECT_EQ(mesh.name(), "demo_character.body");
  EXPECT_EQ(mesh.asset(), "demo_character");
  EXPECT_EQ(mesh.skeleton(), "demo_character");
  EXPECT_GE(mesh.vertex_count(), 4000);
  EXPECT_LE(mesh.vertex_count(), 12000);
  EXPECT_EQ(mesh.max_influences(), 4);

  // Its skeleton is the demo walk's, joint for joint.
  const v1::Skeleton skeleton = client.GetSkeleton(mesh.skeleton());
  const v1::Skeleton walk_skeleton = client.GetSkeleton("demo_walk");
  ASSERT_EQ(skeleton.joints_size(), 19);
  ASSERT_EQ(skeleton.joints_size(), walk_skeleton.joints_size());
  for (int j = 0; j < skeleton.joints_size(); ++j) {
    EXPECT_EQ(skeleton.joints(j).name(), walk_skeleton.joints(j).name());
    EXPECT_EQ(skeleton.joints(j).parent(), walk_skeleton.joints(j).parent());
  }

  // One clip animates that skeleton: the walk, as long as demo_walk.
  std::vector<v1::ClipInfo> clips;
  const auto listed = client.ListClips();
  for (const auto& c : listed.clips())
    if (c.skeleton() == mesh.skeleton()) clips.push_back(c);
  ASSERT_EQ(clips.size(), 1u);
  EXPECT_EQ(clips[0].name(), "demo_character.walk");
  EXPECT_NEAR(clips[0].duration(), client.GetClip("demo_walk").duration(), 1e-6);

  // Skinned by it, LBS and DQS: finite positions and unit normals for every
  // vertex, close to each other.
  auto skin = [&](double time, v1::SkinningMethod method) {
    v1::SkinMeshRequest request;
    request.set_mesh(mesh.name());
    request.set_clip(clips[0].name());
    request.set_time(time);
    request.set_method(method);
    return client.SkinMesh(request);
  };
  const auto lbs = skin(0.5, v1::LBS), dqs = skin(0.5, v1::DQS);
  for (const auto* r : {&lbs, &dqs}) {
    ASSERT_EQ(r->vertex_count(), mesh.vertex_count());
    ASSERT_EQ(r->positions_size(), 3 * mesh.vertex_count());
    ASSERT_EQ(r->normals_size(), 3 * mesh.vertex_count());
    for (float x : r->positions()) ASSERT_TRUE(std::isfinite(x));
    for (int v = 0; v < mesh.vertex_count(); ++v)
      ASSERT_NEAR(std::hypot(r->normals(3 * v), r->normals(3 * v + 1), r->normals(3 * v + 2)), 1.0, 1e-3) << v;
  }
  double largest_difference = 0;
  for (int i = 0; i < lbs.positions_size(); ++i)
    largest_difference = std::max(largest_difference, double(std::abs(lbs.positions(i) - dqs.positions(i))));
  EXPECT_GT(largest_difference, 0.0) << "LBS and DQS gave identical bodies";
  EXPECT_LT(largest_difference, 5.0) << "cm";
  // One stride later (the cycle is 1 s) the pose repeats 110 cm further along +Z.
  const auto later = skin(1.5, v1::LBS);
  EXPECT_NEAR(Mean(later.positions(), 2) - Mean(lbs.positions(), 2), kDemoWalkSpeed * kDemoWalkCycleSeconds, 0.05)
      << "cm";
  EXPECT_NEAR(Mean(later.positions(), 0), Mean(lbs.positions(), 0), 0.05) << "cm";
  EXPECT_NEAR(Mean(later.positions(), 1), Mean(lbs.positions(), 1), 0.05) << "cm";
}

TEST(DemoAssets, ReplicasSeedingOneNewDataDirKeepOneCopyOfEach) {
  TempDir data;
  std::optional<ServerProcess> a, b;
  std::thread start_a([&] { a.emplace(data.path()); });
  std::thread start_b([&] { b.emplace(data.path()); });
  start_a.join();
  start_b.join();
  // A replica that opened the data dir after the other's first import finds
  // it seeded and seeds nothing: it gets the rest from the manifest, which
  // servers check every 500 ms.
  const std::set<std::string> both = {"demo_character", "demo_walk"};
  for (ServerProcess* server : {&*a, &*b}) {
    client::Client client(OptionsFor(*server));
    EXPECT_TRUE(WaitFor([&] { return AssetNames(client) == both; }, kPropagationTimeoutSeconds))
        << ReadFile(server->log_file());
    EXPECT_EQ(client.GetMesh("demo_character.body").skeleton(), "demo_character");
    EXPECT_EQ(ReadFile(server->log_file()).find("could not seed"), std::string::npos) << ReadFile(server->log_file());
  }
  // A restart finds the data dir seeded: nothing is seeded again.
  a.reset();
  b.reset();
  ServerProcess again(data.path());
  client::Client client(OptionsFor(again));
  EXPECT_EQ(AssetNames(client), both);
  EXPECT_EQ(ReadFile(again.log_file()).find("seeded demo"), std::string::npos) << ReadFile(again.log_file());
}

TEST(DemoAssets, NoDemoSeedsNothing) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  EXPECT_TRUE(AssetNames(client).empty());
  EXPECT_EQ(client.ListMeshes().meshes_size(), 0);
}

}  // namespace
}  // namespace armature::testing
