// What the server holds stays within stated bounds: an import is refused
// before it decodes past the room left under --max-assets-mb, imports stop at
// that total, a bake counts the clip it makes in memory, and compressing a
// long clip holds about what the clip holds. Peaks are the server process's
// VmHWM.
#include <cmath>
#include <csignal>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/metrics_scrape.h"
#include "support/process_memory.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

constexpr int64_t kMiB = 1024;  // in kB, as /proc counts

// 8 meshes sharing one accessor of 4,999,998 VEC3 zeros without a bufferView:
// a few hundred bytes that decode to 8 meshes of 5 M vertices each.
std::string SharedAccessorBomb() {
  nlohmann::json g = {{"asset", {{"version", "2.0"}}},
                      {"accessors", {{{"componentType", 5126}, {"count", 4999998}, {"type", "VEC3"}}}},
                      {"meshes", nlohmann::json::array()}};
  for (int m = 0; m < 8; ++m) g["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}});
  return g.dump();
}

TEST(MemoryBounds, ASharedAccessorBombIsRefusedBeforeItDecodes) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  const std::string bomb = SharedAccessorBomb();
  ASSERT_LT(bomb.size(), 1000u);
  const grpc::Status st = StatusOf([&] { client.Import({"bomb.gltf", bomb}); });
  EXPECT_EQ(st.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << st.error_message();
  EXPECT_NE(st.error_message().find("max_decoded_bytes"), std::string::npos) << st.error_message();
  EXPECT_NE(st.error_message().find("--max-assets-mb"), std::string::npos) << st.error_message();
  const int64_t peak = StatusKb(server.pid(), "VmHWM");
  std::printf("  687-byte-class bomb (%zu bytes): server peak %.0f MB\n", bomb.size(), peak / 1024.0);
  // The default --max-assets-mb is 1024: decoding stops below it (was 2.77 GB, accepted).
  EXPECT_LT(peak, 1024 * kMiB);
  EXPECT_TRUE(client.ListAssets().assets().empty());

  // With less room, it stops at the first mesh.
  TempDir small_data;
  ServerProcess small(small_data.path(), {"--no-demo", "--max-assets-mb", "64"});
  client::Client small_client(OptionsFor(small));
  EXPECT_EQ(CodeOf([&] { small_client.Import({"bomb.gltf", bomb}); }), grpc::StatusCode::RESOURCE_EXHAUSTED);
  const int64_t small_peak = StatusKb(small.pid(), "VmHWM");
  std::printf("  with --max-assets-mb 64: server peak %.0f MB\n", small_peak / 1024.0);
  EXPECT_LT(small_peak, 200 * kMiB);
}

TEST(MemoryBounds, ImportsStopAtMaxAssetsMbAndResumeAfterADelete) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-assets-mb", "4"});
  client::Client client(OptionsFor(server));
  const std::string walk = ArmBvhWithFrames(10000);  // a clip of about 1 MB in memory, kept exact
  int imported = 0;
  grpc::Status refused;
  for (int i = 0; i < 20 && refused.ok(); ++i) {
    refused = StatusOf([&] { client.Import({"walk.bvh", walk}, "walk" + std::to_string(i), "", false, {}, "exact"); });
    if (refused.ok()) ++imported;
  }
  EXPECT_GE(imported, 1);
  EXPECT_LT(imported, 20) << "never refused";
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << refused.error_message();
  EXPECT_NE(refused.error_message().find("--max-assets-mb"), std::string::npos) << refused.error_message();
  EXPECT_NE(refused.error_message().find("in memory"), std::string::npos) << refused.error_message();
  const double held = ScrapeSample(server, "armature_assets_memory_bytes");
  EXPECT_LE(held, 4.0 * (1 << 20));
  EXPECT_EQ(client.ListAssets().assets_size(), imported);
  // A delete makes room again.
  client.DeleteAsset("walk0");
  EXPECT_EQ(CodeOf([&] { client.Import({"walk.bvh", walk}, "again", "", false, {}, "exact"); }), grpc::StatusCode::OK);
}

TEST(MemoryBounds, ABakeCountsTheClipInMemoryNotOnlyTheFile) {
  TempDir data;
  ServerProcess server(data.path());
  client::Client client(OptionsFor(server));
  const int64_t before = StatusKb(server.pid(), "VmHWM");
  // demo_walk at 1,000 fps for 392 s: a file of about 255 MB, under
  // --max-upload-mb, but about 1.8 GB while made and stored.
  v1::CreateClipRequest request;
  request.set_name("long_bake");
  request.set_skeleton("demo_walk");
  request.mutable_bake()->mutable_motion()->add_layers()->set_clip("demo_walk");
  request.mutable_bake()->set_fps(1000);
  request.mutable_bake()->set_duration(392);
  EXPECT_LT(request.ByteSizeLong(), 200u);
  const grpc::Status st = StatusOf([&] { client.CreateClip(request); });
  EXPECT_EQ(st.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << st.error_message();
  EXPECT_NE(st.error_message().find("in memory"), std::string::npos) << st.error_message();
  EXPECT_NE(st.error_message().find("--max-upload-mb"), std::string::npos) << st.error_message();
  const int64_t peak = StatusKb(server.pid(), "VmHWM");
  std::printf("  bake of 392 s at 1000 fps: server peak %.0f MB (%.0f MB before)\n", peak / 1024.0, before / 1024.0);
  EXPECT_LT(peak - before, 64 * kMiB);

  // A bake within the bound is still made.
  request.set_name("short_bake");
  request.mutable_bake()->set_duration(10);
  EXPECT_EQ(CodeOf([&] { client.CreateClip(request); }), grpc::StatusCode::OK);
  EXPECT_EQ(server.Stop(SIGTERM), 0);
}

// A BVH of a root and a chain of 30 joints, at 120 fps, every channel
// moving (sines of different periods), so that every track is animated.
std::string ChainBvh(int frames) {
  constexpr int kChain = 30;
  std::string bvh =
      "HIERARCHY\nROOT hips\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation "
      "Xrotation Yrotation\n";
  for (int j = 0; j < kChain; ++j)
    bvh += "JOINT j" + std::to_string(j) + "\n{\n  OFFSET 0 5 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n";
  bvh += "End Site\n{\n  OFFSET 0 5 0\n}\n";
  for (int j = 0; j <= kChain; ++j) bvh += "}\n";
  bvh += "MOTION\nFrames: " + std::to_string(frames) + "\nFrame Time: 0.0083333\n";
  char value[16];
  for (int f = 0; f < frames; ++f) {
    for (int c = 0; c < 6 + 3 * kChain; ++c) {
      std::snprintf(value, sizeof value, "%.2f ", 20 * std::sin(f * (0.01 + 0.001 * c)));
      bvh += value;
    }
    bvh += "\n";
  }
  return bvh;
}

TEST(MemoryBounds, ALongClipIsCompressedInAboutTheMemoryItTakes) {
  constexpr int kFrames = 40000;  // 1.24 M joint-samples: about 50 MB as parsed
  const std::string bvh = ChainBvh(kFrames);
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  const int64_t before = StatusKb(server.pid(), "VmHWM");
  const v1::ImportAssetResponse imported = client.Import({"chain.bvh", bvh});
  ASSERT_EQ(imported.asset().clips_size(), 1);
  EXPECT_FALSE(imported.asset().clips(0).exact()) << "kept exact, not compressed";
  const int64_t peak = StatusKb(server.pid(), "VmHWM");
  const double joint_samples = 31.0 * kFrames;
  const double per_joint_sample = (peak - before) * 1024.0 / joint_samples;
  std::printf(
      "  a %.0f MB BVH of %.2f M joint-samples: server peak %.0f MB (%.0f MB before), %.0f bytes a joint-sample\n",
      bvh.size() / 1048576.0, joint_samples / 1e6, peak / 1024.0, before / 1024.0, per_joint_sample);
  // The upload, the parsed clip (about 41 bytes a joint-sample) and the
  // compressor's working set (about 50) at once. When the compressor kept
  // every frame's local and world poses (245 bytes), this was 331; it is
  // about 130 now.
  EXPECT_LT(per_joint_sample, 200) << "peak " << peak << " kB, before " << before << " kB";
}

}  // namespace
}  // namespace armature::testing
