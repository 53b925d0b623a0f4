// Servers on one S3 bucket (--store) served by a real s3rver: the fixture
// sets the credentials s3rver accepts and starts replicas, each with its own
// cache dir. Shared by the store tests.
#pragma once

#include <stdlib.h>

#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "common/s3rver_process.h"
#include "support/client_helpers.h"
#include "support/http_get.h"
#include "support/server_process.h"

namespace armature::testing {

class StoreTest : public ::testing::Test {
 public:
  // The server's /healthz answer, its "store" member included.
  static std::string StoreHealthOf(const ServerProcess& server) {
    return HttpGet("http://127.0.0.1:" + std::to_string(server.http_port()) + "/healthz").body;
  }

 protected:
  void SetUp() override {
    for (const char* name : {"AWS_SESSION_TOKEN", "AWS_PROFILE", "AWS_SHARED_CREDENTIALS_FILE"}) unsetenv(name);
    setenv("AWS_ACCESS_KEY_ID", "S3RVER", 1);
    setenv("AWS_SECRET_ACCESS_KEY", "S3RVER", 1);
    setenv("AWS_REGION", "us-east-1", 1);
  }
  // A replica on `url` with a fresh cache dir, polling every `poll_ms`.
  std::unique_ptr<ServerProcess> Replica(const std::string& url, int poll_ms = 1000,
                                         std::vector<std::string> extra = {}) {
    caches_.push_back(std::make_unique<TempDir>());
    return ReplicaOn(caches_.back()->path(), url, poll_ms, std::move(extra));
  }
  static std::unique_ptr<ServerProcess> ReplicaOn(const std::filesystem::path& cache, const std::string& url,
                                                  int poll_ms = 1000, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"--no-demo", "--store", url, "--store-poll-ms", std::to_string(poll_ms)};
    args.insert(args.end(), extra.begin(), extra.end());
    return std::make_unique<ServerProcess>(cache, args);
  }
  // Runs armature-server to its exit (it must not start) and returns its code and output.
  static CommandResult RunServerToExit(const std::filesystem::path& cache, const std::string& url) {
    return RunCommand("timeout 60 " + ShellQuote(ARMATURE_SERVER_BIN) + " --no-demo --grpc-port 0 --http-port 0 " +
                      "--data-dir " + ShellQuote(cache.string()) + " --store " + ShellQuote(url));
  }

  std::vector<std::unique_ptr<TempDir>> caches_;
};

// The version each asset of `client`'s server lists, by name.
inline std::map<std::string, std::string> VersionsOf(client::Client& client) {
  std::map<std::string, std::string> versions;
  const v1::ListAssetsResponse listed = client.ListAssets();
  for (const auto& a : listed.assets()) versions[a.name()] = a.version();
  return versions;
}

}  // namespace armature::testing
