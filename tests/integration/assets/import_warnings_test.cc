// Import warnings reach the caller: gRPC ImportAssetResponse.warnings, the
// REST JSON field `warnings`, and `armature import`'s "warnings":[…].
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

// One joint whose matrix has shear: imported, with a warning saying so.
constexpr char kShearedGltf[] = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
  "nodes":[{"name":"sheared","matrix":[1,0,0,0, 1,1,0,0, 0,0,1,0, 0,0,0,1]}]})";

TEST(ImportWarnings, ReachGrpcRestAndTheCli) {
  TempDir data, files;
  ServerProcess server(data.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  const auto grpc_answer = client.Import({"sheared.gltf", kShearedGltf});
  ASSERT_EQ(grpc_answer.warnings_size(), 1);
  EXPECT_NE(grpc_answer.warnings(0).find("shear"), std::string::npos) << grpc_answer.warnings(0);
  EXPECT_EQ(client.Import({"arm.bvh", kArmBvh}).warnings_size(), 0);

  const auto file = WriteTemp(files, "sheared.gltf", kShearedGltf);
  const auto rest = RunCommand("curl -s -X POST -H 'Content-Type: application/octet-stream' --data-binary @" +
                               ShellQuote(file.string()) + " 'http://127.0.0.1:" + std::to_string(server.http_port()) +
                               "/v1/assets:import?filename=sheared.gltf&name=rest'");
  ASSERT_EQ(rest.exit_code, 0) << rest.err;
  const auto rest_json = nlohmann::json::parse(rest.out);
  ASSERT_TRUE(rest_json.contains("warnings")) << rest.out;
  EXPECT_NE(rest_json["warnings"][0].get<std::string>().find("shear"), std::string::npos) << rest.out;

  const auto cli = RunCli(server.target(), {"import", file.string(), "--name", "cli"});
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  const auto cli_json = nlohmann::json::parse(cli.out);
  ASSERT_EQ(cli_json["warnings"].size(), 1u) << cli.out;
  EXPECT_NE(cli_json["warnings"][0].get<std::string>().find("shear"), std::string::npos) << cli.out;
}

}  // namespace
}  // namespace armature::testing
