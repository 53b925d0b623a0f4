// DELETE of a clip that shares its asset with other parts is refused (FAILED_PRECONDITION over
// gRPC, 400 over REST) naming the asset and what else it holds; nothing is deleted. The asset's
// own name, or a BVH's clip (which is its asset), still deletes.
#include <gtest/gtest.h>
#include <httplib.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

constexpr char kRefusal[] =
    "clip 'demo_character.walk' belongs to asset 'demo_character', which also holds 1 mesh and 1 skeleton; "
    "delete the asset 'demo_character' to remove them all";

TEST(DeletePart, AClipOfALargerAssetIsRefusedOverGrpcAndRestAndNothingIsDeleted) {
  TempDir data;
  ServerProcess server(data.path());
  client::Client client(OptionsFor(server));
  const grpc::Status refused = StatusOf([&] { client.DeleteAsset("demo_character.walk"); });
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_EQ(refused.error_message(), kRefusal);

  httplib::Client http("127.0.0.1", server.http_port());
  const auto rest = http.Delete("/v1/clips/demo_character.walk");
  ASSERT_TRUE(rest);
  EXPECT_EQ(rest->status, 400) << rest->body;
  EXPECT_NE(rest->body.find(kRefusal), std::string::npos) << rest->body;

  // Still all there: the clip, the mesh, the asset.
  EXPECT_EQ(client.GetClip("demo_character.walk").name(), "demo_character.walk");
  EXPECT_TRUE(AssetNames(client).count("demo_character"));

  // A BVH's clip is its asset: deleting it by the clip route works.
  const auto bvh = http.Delete("/v1/clips/demo_walk");
  ASSERT_TRUE(bvh);
  EXPECT_EQ(bvh->status, 200) << bvh->body;
  EXPECT_FALSE(AssetNames(client).count("demo_walk"));
  // The whole asset by its name.
  EXPECT_EQ(client.DeleteAsset("demo_character").name(), "demo_character");
  EXPECT_FALSE(AssetNames(client).count("demo_character"));
}

}  // namespace
}  // namespace armature::testing
