#include "server/assets/bucket/aws_credentials.h"

#include <stdlib.h>

#include <gtest/gtest.h>

#include <fstream>

#include "../../testing/temp_store.h"

namespace armature::server {
namespace {

// Clears the AWS variables for a test and puts them back after.
class AwsEnv : public ::testing::Test {
 protected:
  static constexpr const char* kNames[] = {
      "AWS_ACCESS_KEY_ID",  "AWS_SECRET_ACCESS_KEY", "AWS_SESSION_TOKEN",           "AWS_REGION",
      "AWS_DEFAULT_REGION", "AWS_PROFILE",           "AWS_SHARED_CREDENTIALS_FILE", "HOME"};
  void SetUp() override {
    for (const char* name : kNames) {
      if (const char* v = getenv(name)) saved_.emplace_back(name, v);
      unsetenv(name);
    }
    setenv("HOME", home_.path().c_str(), 1);
  }
  void TearDown() override {
    for (const char* name : kNames) unsetenv(name);
    for (const auto& [name, value] : saved_) setenv(name.c_str(), value.c_str(), 1);
  }
  std::vector<std::pair<std::string, std::string>> saved_;
  test_util::TempDir home_;
};

TEST_F(AwsEnv, FromTheEnvironmentWithASessionToken) {
  setenv("AWS_ACCESS_KEY_ID", "AKID", 1);
  setenv("AWS_SECRET_ACCESS_KEY", "SECRET", 1);
  setenv("AWS_SESSION_TOKEN", "TOKEN", 1);
  setenv("AWS_REGION", "eu-west-3", 1);
  auto c = LoadAwsCredentials();
  ASSERT_TRUE(c.ok()) << c.status().message();
  EXPECT_EQ(c->access_key_id, "AKID");
  EXPECT_EQ(c->secret_access_key, "SECRET");
  EXPECT_EQ(c->session_token, "TOKEN");
  EXPECT_EQ(c->region, "eu-west-3");
  EXPECT_EQ(c->source.find("SECRET"), std::string::npos);
}

TEST_F(AwsEnv, FromTheDefaultFileAProfileAndBoth) {
  std::filesystem::create_directories(home_.path() / ".aws");
  std::ofstream(home_.path() / ".aws" / "credentials")
      << "[default]\naws_access_key_id = DEF\naws_secret_access_key = DEFSECRET\n\n"
         "[ci]\naws_access_key_id=CI\naws_secret_access_key=CISECRET\naws_session_token = CITOKEN\nregion = "
         "ap-south-1\n";
  auto def = LoadAwsCredentials();
  ASSERT_TRUE(def.ok()) << def.status().message();
  EXPECT_EQ(def->access_key_id, "DEF");
  EXPECT_EQ(def->region, "us-east-1");
  setenv("AWS_PROFILE", "ci", 1);
  auto ci = LoadAwsCredentials();
  ASSERT_TRUE(ci.ok());
  EXPECT_EQ(ci->access_key_id, "CI");
  EXPECT_EQ(ci->session_token, "CITOKEN");
  EXPECT_EQ(ci->region, "ap-south-1");
  // Both: keys from the file, the region from the environment.
  setenv("AWS_REGION", "us-west-2", 1);
  EXPECT_EQ(LoadAwsCredentials()->region, "us-west-2");
  // The environment's keys win over the file's.
  setenv("AWS_ACCESS_KEY_ID", "ENV", 1);
  setenv("AWS_SECRET_ACCESS_KEY", "ENVSECRET", 1);
  EXPECT_EQ(LoadAwsCredentials()->access_key_id, "ENV");
}

TEST_F(AwsEnv, AnotherFileByVariableAndNoneAtAll) {
  EXPECT_EQ(LoadAwsCredentials().status().code(), StatusCode::kFailedPrecondition);
  const auto file = home_.path() / "elsewhere.ini";
  std::ofstream(file) << "[default]\naws_access_key_id = F\naws_secret_access_key = FS\n";
  setenv("AWS_SHARED_CREDENTIALS_FILE", file.c_str(), 1);
  auto c = LoadAwsCredentials();
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c->access_key_id, "F");
  EXPECT_NE(c->source.find("elsewhere.ini"), std::string::npos);
}

}  // namespace
}  // namespace armature::server
