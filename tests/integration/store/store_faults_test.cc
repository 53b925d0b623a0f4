// A bucket that goes away, denied credentials, no bucket, corrupt versions:
// real servers on a real S3-compatible server (s3rver).
#include <chrono>
#include <csignal>
#include <thread>

#include "support/metrics_scrape.h"
#include "store/store_fixture.h"

namespace armature::testing {
namespace {

bool Reachable(const ServerProcess& server) {
  return StoreTest::StoreHealthOf(server).find("\"reachable\":true") != std::string::npos;
}

TEST_F(StoreTest, TheBucketGoneAndBack) {
  S3rverProcess s3({"bucket"});
  auto a = Replica(s3.Url("bucket"), 200);
  client::Client ca(OptionsFor(*a));
  ca.Import({"arm.bvh", kArmBvh});
  EXPECT_NE(StoreHealthOf(*a).find("\"kind\":\"bucket\""), std::string::npos) << StoreHealthOf(*a);
  ASSERT_TRUE(Reachable(*a));

  s3.Stop();
  ASSERT_TRUE(WaitFor([&] { return !Reachable(*a); }, 30)) << StoreHealthOf(*a);
  // What is loaded is served; imports fail UNAVAILABLE, saying why and where.
  EXPECT_EQ(ca.GetClip("arm").frames(), 3);
  const grpc::Status failed = StatusOf([&] { ca.Import({"leg.bvh", kArmBvh}); });
  EXPECT_EQ(failed.error_code(), grpc::StatusCode::UNAVAILABLE);
  EXPECT_NE(failed.error_message().find("unavailable"), std::string::npos) << failed.error_message();
  EXPECT_NE(failed.error_message().find("127.0.0.1:" + std::to_string(s3.port())), std::string::npos)
      << failed.error_message();
  EXPECT_EQ(CodeOf([&] { ca.DeleteAsset("arm"); }), grpc::StatusCode::UNAVAILABLE);

  s3.Restart();  // the same port and objects: the bucket is back
  EXPECT_TRUE(WaitFor([&] { return Reachable(*a); }, 30)) << StoreHealthOf(*a);
  ca.Import({"leg.bvh", kArmBvh});
  auto b = Replica(s3.Url("bucket"), 200);
  client::Client cb(OptionsFor(*b));
  EXPECT_EQ(AssetNames(cb), (std::set<std::string>{"arm", "leg"}));
  EXPECT_NE(ReadFile(a->log_file()).find("reachable again"), std::string::npos);
}

TEST_F(StoreTest, UnreachableAtStartServesTheCacheElseExitsNamingTheEndpoint) {
  S3rverProcess s3({"bucket"});
  TempDir cache, empty;
  {
    auto a = ReplicaOn(cache.path(), s3.Url("bucket"));
    client::Client(OptionsFor(*a)).Import({"arm.bvh", kArmBvh});
    ASSERT_EQ(a->Stop(SIGTERM), 0);
  }
  s3.Stop();
  const CommandResult cold = RunServerToExit(empty.path(), s3.Url("bucket"));
  EXPECT_NE(cold.exit_code, 0);
  EXPECT_NE(cold.err.find("http://127.0.0.1:" + std::to_string(s3.port()) + "/bucket"), std::string::npos) << cold.err;
  EXPECT_NE(cold.err.find("no cache"), std::string::npos) << cold.err;

  auto warm = ReplicaOn(cache.path(), s3.Url("bucket"), 200);
  client::Client cw(OptionsFor(*warm));
  EXPECT_EQ(cw.GetClip("arm").frames(), 3);
  EXPECT_NE(ReadFile(warm->log_file()).find("unreachable at start: serving the 1 cached assets"), std::string::npos)
      << ReadFile(warm->log_file());
  EXPECT_NE(StoreHealthOf(*warm).find("\"serving_cache\":true"), std::string::npos) << StoreHealthOf(*warm);
  s3.Restart();
  EXPECT_TRUE(WaitFor([&] { return Reachable(*warm); }, 30));
  cw.Import({"leg.bvh", kArmBvh});
}

TEST_F(StoreTest, DeniedCredentialsAndAMissingBucketStopTheStartClearly) {
  // s3rver checks that the access key exists, not the SigV4 signature: an
  // unknown key is what it can deny (InvalidAccessKeyId, HTTP 403).
  S3rverProcess s3({"bucket"});
  TempDir cache;
  setenv("AWS_ACCESS_KEY_ID", "NOT-A-KEY", 1);
  const CommandResult denied = RunServerToExit(cache.path(), s3.Url("bucket"));
  EXPECT_NE(denied.exit_code, 0);
  EXPECT_NE(denied.err.find("InvalidAccessKeyId"), std::string::npos) << denied.err;
  EXPECT_NE(denied.err.find("check the credentials (the environment (AWS_ACCESS_KEY_ID))"), std::string::npos)
      << denied.err;
  EXPECT_EQ(denied.err.find("S3RVER"), std::string::npos) << "the secret must never be printed";
  unsetenv("AWS_ACCESS_KEY_ID");
  unsetenv("AWS_SECRET_ACCESS_KEY");
  setenv("AWS_SHARED_CREDENTIALS_FILE", (cache.path() / "none").c_str(), 1);
  const CommandResult none = RunServerToExit(cache.path(), s3.Url("bucket"));
  EXPECT_NE(none.exit_code, 0);
  EXPECT_NE(none.err.find("no object store credentials"), std::string::npos) << none.err;
  SetUp();
  const CommandResult missing = RunServerToExit(cache.path(), s3.Url("no-such-bucket"));
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.err.find("NoSuchBucket"), std::string::npos) << missing.err;
}

TEST_F(StoreTest, CredentialsFromAFileWithASessionToken) {
  S3rverProcess s3({"bucket"});
  TempDir home;
  std::ofstream(home.path() / "credentials")
      << "[default]\naws_access_key_id = NOPE\naws_secret_access_key = x\n"
         "[armature]\naws_access_key_id = S3RVER\naws_secret_access_key = S3RVER\naws_session_token = tok\n";
  unsetenv("AWS_ACCESS_KEY_ID");
  unsetenv("AWS_SECRET_ACCESS_KEY");
  setenv("AWS_SHARED_CREDENTIALS_FILE", (home.path() / "credentials").c_str(), 1);
  setenv("AWS_PROFILE", "armature", 1);
  auto a = Replica(s3.Url("bucket"));
  unsetenv("AWS_PROFILE");
  client::Client(OptionsFor(*a)).Import({"arm.bvh", kArmBvh});
  EXPECT_NE(ReadFile(a->log_file()).find("profile 'armature'"), std::string::npos) << ReadFile(a->log_file());
}

}  // namespace
}  // namespace armature::testing
