#include "server/assets/bucket/aws_credentials.h"

#include <cstdlib>
#include <fstream>
#include <map>

namespace armature::server {
namespace {

std::string Env(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "";
}

std::string Trim(std::string s) {
  const size_t begin = s.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  return s.substr(begin, s.find_last_not_of(" \t\r") - begin + 1);
}

// The key = value lines of one [profile] section of an INI file.
std::map<std::string, std::string> ReadProfile(const std::string& path, const std::string& profile) {
  std::map<std::string, std::string> values;
  std::ifstream in(path);
  std::string line, section;
  while (std::getline(in, line)) {
    line = Trim(line);
    if (line.empty() || line[0] == '#' || line[0] == ';') continue;
    if (line.front() == '[' && line.back() == ']') {
      section = Trim(line.substr(1, line.size() - 2));
      continue;
    }
    const size_t eq = line.find('=');
    if (section == profile && eq != std::string::npos) values[Trim(line.substr(0, eq))] = Trim(line.substr(eq + 1));
  }
  return values;
}

}  // namespace

StatusOr<AwsCredentials> LoadAwsCredentials() {
  AwsCredentials creds;
  const std::string profile = Env("AWS_PROFILE").empty() ? "default" : Env("AWS_PROFILE");
  std::string file = Env("AWS_SHARED_CREDENTIALS_FILE");
  if (file.empty() && !Env("HOME").empty()) file = Env("HOME") + "/.aws/credentials";
  const auto from_file = file.empty() ? std::map<std::string, std::string>() : ReadProfile(file, profile);
  auto value = [&](const char* key) {
    auto it = from_file.find(key);
    return it == from_file.end() ? std::string() : it->second;
  };
  if (!Env("AWS_ACCESS_KEY_ID").empty() && !Env("AWS_SECRET_ACCESS_KEY").empty()) {
    creds.access_key_id = Env("AWS_ACCESS_KEY_ID");
    creds.secret_access_key = Env("AWS_SECRET_ACCESS_KEY");
    creds.session_token = Env("AWS_SESSION_TOKEN");
    creds.source = "the environment (AWS_ACCESS_KEY_ID)";
  } else if (!value("aws_access_key_id").empty() && !value("aws_secret_access_key").empty()) {
    creds.access_key_id = value("aws_access_key_id");
    creds.secret_access_key = value("aws_secret_access_key");
    creds.session_token = value("aws_session_token");
    creds.source = "profile '" + profile + "' of " + file;
  } else {
    return Status::FailedPrecondition(
        "no object store credentials: set AWS_ACCESS_KEY_ID and AWS_SECRET_ACCESS_KEY, or give profile '" + profile +
        "' aws_access_key_id and aws_secret_access_key in " + (file.empty() ? "~/.aws/credentials" : file));
  }
  for (const std::string& region : {Env("AWS_REGION"), Env("AWS_DEFAULT_REGION"), value("region")})
    if (!region.empty()) {
      creds.region = region;
      break;
    }
  return creds;
}

}  // namespace armature::server
