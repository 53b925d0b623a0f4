// Clips held in their compressed runtime form (issue 30) by a real server:
// ListClips shows each clip's bytes, bytes per joint-sample, bound and worst
// error; armature_assets_memory_bytes counts the compressed form; an import's
// precision is checked, kept in the manifest and read back at load.
#include <string>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/metrics_scrape.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

constexpr double kDefaultBoundCm = 0.01;  // the server's default --clip-error
constexpr double kCmuJointSamples = 31.0 * 2752;

TEST(RuntimeClips, ListingsAndMemoryShowTheCompressedForm) {
  const std::string cmu = SharedData("bvh/cmu_01_01.bvh");
  if (cmu.empty()) GTEST_SKIP() << "shared data bvh/cmu_01_01.bvh is absent";
  TempDir data;
  double lossy_memory = 0;
  v1::ClipInfo lossy;
  {
    ServerProcess server(data.path(), {"--no-demo"});
    client::Client client(OptionsFor(server));
    client.ImportFile(cmu, "cmu");
    lossy = client.GetClip("cmu");
    EXPECT_FALSE(lossy.exact());
    EXPECT_EQ(lossy.error_bound_cm(), kDefaultBoundCm);
    EXPECT_GT(lossy.worst_error_cm(), 0);
    EXPECT_LE(lossy.worst_error_cm(), kDefaultBoundCm);
    EXPECT_LE(lossy.p99_error_cm(), lossy.worst_error_cm());
    EXPECT_NEAR(lossy.bytes_per_joint_sample(), lossy.runtime_bytes() / kCmuJointSamples, 1e-9);
    EXPECT_LE(lossy.bytes_per_joint_sample(), 2.5);
    lossy_memory = ScrapeSample(server, "armature_assets_memory_bytes");
    std::printf("  CMU 01_01 at the default bound: %.3f B/joint-sample, worst %.4f cm; held %.3f B/joint-sample\n",
                lossy.bytes_per_joint_sample(), lossy.worst_error_cm(), lossy_memory / kCmuJointSamples);
    // Everything counted (the skeleton and the clip's bookkeeping too), within 10% of the form itself.
    EXPECT_LE(lossy_memory, 1.1 * static_cast<double>(lossy.runtime_bytes()) + 16384);

    client.ImportFile(cmu, "cmu_exact", false, false, "", "exact");
    const v1::ClipInfo exact = client.GetClip("cmu_exact");
    EXPECT_TRUE(exact.exact());
    EXPECT_EQ(exact.worst_error_cm(), 0);
    const double exact_memory = ScrapeSample(server, "armature_assets_memory_bytes") - lossy_memory;
    std::printf("  kept exact: %.3f B/joint-sample held\n", exact_memory / kCmuJointSamples);
    EXPECT_GT(exact_memory, 10 * lossy_memory);  // the drop: the file form of doubles is not held beside it

    const grpc::Status zero = StatusOf([&] { client.ImportFile(cmu, "zero", false, false, "", "0"); });
    EXPECT_EQ(zero.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_EQ(zero.error_message().rfind("precision: '0' is not a bound", 0), 0u) << zero.error_message();
  }
  // Loaded from the data dir: each clip as its import asked.
  ServerProcess again(data.path(), {"--no-demo", "--clip-error", "exact"});
  client::Client client(OptionsFor(again));
  EXPECT_TRUE(client.GetClip("cmu_exact").exact());
  const v1::ClipInfo reloaded = client.GetClip("cmu");
  EXPECT_FALSE(reloaded.exact());
  EXPECT_EQ(reloaded.runtime_bytes(), lossy.runtime_bytes());
  EXPECT_EQ(reloaded.worst_error_cm(), lossy.worst_error_cm());
}

}  // namespace
}  // namespace armature::testing
