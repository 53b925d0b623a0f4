// Every call gets an answer: an exception in a handler (here an allocation
// failure inside an import) ends the call with a status and a message.
#include <sys/resource.h>

#include <chrono>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

// The process's virtual memory size in bytes (VmSize in /proc/<pid>/status).
long long VirtualBytes(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmSize:", 0) == 0) return std::stoll(line.substr(7)) * 1024;
  return -1;
}

TEST(CallBoundary, OutOfMemoryInAnImportIsAnsweredAndTheServerGoesOn) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-upload-mb", "4096", "--max-message-mb", "8"});
  client::Client client(OptionsFor(server));
  client.Import({"arm.bvh", kArmBvh});
  const long long base = VirtualBytes(server.pid());
  ASSERT_GT(base, 0);
  // Room for the server's ordinary allocations, not for an upload buffer of hundreds of MB.
  const rlimit cap{static_cast<rlim_t>(base + (384ll << 20)), static_cast<rlim_t>(base + (384ll << 20))};
  ASSERT_EQ(::prlimit(server.pid(), RLIMIT_AS, &cap, nullptr), 0);

  client::ClientOptions options = OptionsFor(server);
  options.timeout = std::chrono::seconds(60);
  const auto started = std::chrono::steady_clock::now();
  const grpc::Status status = StatusOf([&] {
    client::Client(options).Import({"huge.bvh", std::string(600u << 20, ' ')});
  });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
  EXPECT_NE(status.error_message().find("out of memory"), std::string::npos) << status.error_message();
  EXPECT_LT(seconds, 50) << "answered only at the deadline";
  EXPECT_NE(ReadFile(server.log_file()).find("ImportAsset: out of memory"), std::string::npos);
  // The server goes on; the failed upload left nothing behind.
  EXPECT_EQ(AssetNames(client), std::set<std::string>{"arm"});
  EXPECT_EQ(server.Stop(SIGTERM), 0);
}

}  // namespace
}  // namespace armature::testing
