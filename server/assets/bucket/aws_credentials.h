// The credentials that sign object store requests, found as the AWS tools
// find them: AWS_ACCESS_KEY_ID and AWS_SECRET_ACCESS_KEY (with
// AWS_SESSION_TOKEN) from the environment, else the profile AWS_PROFILE (or
// "default") of the credentials file AWS_SHARED_CREDENTIALS_FILE (or
// ~/.aws/credentials). The region: AWS_REGION, AWS_DEFAULT_REGION, the
// profile's region, else us-east-1 (what S3-compatible servers expect).
#pragma once

#include <string>

#include "armature/base/status.h"

namespace armature::server {

struct AwsCredentials {
  std::string access_key_id{};
  std::string secret_access_key{};
  std::string session_token{};  // empty: none
  std::string region = "us-east-1";
  std::string source{};  // where they came from, for the log (never the secret)
};

// FAILED_PRECONDITION naming where it looked when no credentials are found.
StatusOr<AwsCredentials> LoadAwsCredentials();

}  // namespace armature::server
