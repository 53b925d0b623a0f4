// A second armature-server on a port the first holds exits non-zero naming the port and the
// listener, and the first keeps serving all the calls (no SO_REUSEPORT split of the traffic).
#include <gtest/gtest.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/http_get.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

CommandResult StartSecondServer(const TempDir& data, int grpc_port, int http_port) {
  // `timeout`: before the fix the second server kept running, sharing the ports.
  return RunCommand("timeout 30 " + ShellQuote(ARMATURE_SERVER_BIN) + " --no-demo --host 127.0.0.1 --data-dir " +
                    ShellQuote(data.path().string()) + " --grpc-port " + std::to_string(grpc_port) + " --http-port " +
                    std::to_string(http_port));
}

TEST(PortInUse, ASecondServerOnTheSamePortsExitsAndTheFirstKeepsServing) {
  TempDir first_data, second_data;
  ServerProcess first(first_data.path());
  client::Client client(OptionsFor(first));
  ASSERT_TRUE(AssetNames(client).count("demo_walk"));

  const CommandResult grpc_taken = StartSecondServer(second_data, first.grpc_port(), 0);
  EXPECT_NE(grpc_taken.exit_code, 0);
  EXPECT_NE(
      (grpc_taken.out + grpc_taken.err)
          .find("gRPC listener: port " + std::to_string(first.grpc_port()) + " is in use (another armature-server?)"),
      std::string::npos)
      << grpc_taken.out << grpc_taken.err;

  const CommandResult http_taken = StartSecondServer(second_data, 0, first.http_port());
  EXPECT_NE(http_taken.exit_code, 0);
  EXPECT_NE(
      (http_taken.out + http_taken.err)
          .find("HTTP listener: port " + std::to_string(first.http_port()) + " is in use (another armature-server?)"),
      std::string::npos)
      << http_taken.out << http_taken.err;

  // Every call still reaches the first server (the demo assets it seeded), none an empty one.
  for (int i = 0; i < 10; ++i) {
    client::Client fresh(OptionsFor(first));
    EXPECT_TRUE(AssetNames(fresh).count("demo_walk")) << "call " << i;
    const HttpResponse rest = HttpGet("http://127.0.0.1:" + std::to_string(first.http_port()) + "/v1/assets");
    EXPECT_EQ(rest.status, 200) << rest.error;
    EXPECT_NE(rest.body.find("demo_walk"), std::string::npos) << "call " << i << ": " << rest.body;
  }
}

}  // namespace
}  // namespace armature::testing
