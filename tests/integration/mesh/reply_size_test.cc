// Answers that would outgrow --max-message-mb are refused before the work,
// naming the flag and the computed size (not gRPC's generic size error after
// the server built them).
#include <string>

#include <gtest/gtest.h>

#include "engine/testing/generated_meshes.h"
#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

void ExpectRefusedNamingTheFlag(const grpc::Status& status, const std::string& rpc) {
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
  EXPECT_NE(status.error_message().find("--max-message-mb"), std::string::npos) << status.error_message();
  EXPECT_NE(status.error_message().find(rpc), std::string::npos) << status.error_message();
  EXPECT_NE(status.error_message().find("MiB"), std::string::npos) << status.error_message();
}

TEST(ReplySize, EvaluateClipCountsTimesAndRepeatedJoints) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-message-mb", "1"});
  client::Client client(OptionsFor(server));
  client.Import({"arm.bvh", kArmBvh});
  // 2000 times × 100 joints (one joint repeated) × 28 bytes = 5.6 MB from a 16 KB request.
  v1::EvaluateClipRequest r;
  r.set_clip("arm");
  for (int i = 0; i < 2000; ++i) r.add_times(i * 1e-3);
  for (int i = 0; i < 100; ++i) r.add_joints("Tip");
  const grpc::Status refused = StatusOf([&] { client.EvaluateClip(r); });
  ExpectRefusedNamingTheFlag(refused, "EvaluateClip");
  EXPECT_NE(refused.error_message().find("2000 times x 100 joints"), std::string::npos) << refused.error_message();
  // Under the cap it answers.
  r.clear_joints();
  r.add_joints("Tip");
  EXPECT_EQ(client.EvaluateClip(r).poses_size(), 2000);
}

TEST(ReplySize, ExportClipIsRefusedBeforeWritingFrames) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-message-mb", "0.01"});
  client::Client client(OptionsFor(server));
  client.Import({"long.bvh", ArmBvhWithFrames(400)});  // 400 frames × 2 joints × 27 bytes ≈ 21 KB of BVH
  ExpectRefusedNamingTheFlag(StatusOf([&] { client.ExportClip("long"); }), "ExportClip");
  client.Import({"short.bvh", kArmBvh});
  EXPECT_FALSE(client.ExportClip("short").data().empty());
}

TEST(ReplySize, MeshRepliesAreCheckedAgainstTheCap) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-message-mb", "0.05"});
  // The upload itself must respect the message cap: 16 KB chunks of the ~600 KB OBJ.
  client::ClientOptions options = OptionsFor(server);
  options.upload_chunk_bytes = 16 << 10;
  client::Client client(options);
  // 100 × 100 vertices: 10000 × 12 bytes of positions alone is 120 KB, over 51 KB.
  client.Import({"grid.obj", fixtures::ToObj(fixtures::MakeGrid(100, 100, 1, 1))}, "grid");
  ExpectRefusedNamingTheFlag(StatusOf([&] { client.GetMeshGeometry("grid"); }), "GetMeshGeometry");
  v1::EvaluateBlendshapesRequest blend;
  blend.set_mesh("grid");
  ExpectRefusedNamingTheFlag(StatusOf([&] { client.EvaluateBlendshapes(blend); }), "EvaluateBlendshapes");
}

}  // namespace
}  // namespace armature::testing
