// --auth-token-file: API calls need "authorization: Bearer <token>" and are
// refused before any service code runs; health checks stay open.
#include <cstdlib>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/http_get.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {
namespace fs = std::filesystem;

constexpr char kToken[] = "s3cret-token-one";
constexpr char kRotatedToken[] = "s3cret-token-two";

class Auth : public ::testing::Test {
 protected:
  Auth()
      : token_file_(WriteTemp(files_, "tokens", std::string("\n  ") + kToken + "  \n" + kRotatedToken + "\n")),
        server_(data_.path(), {"--auth-token-file", token_file_.string()}) {}

  client::Client ClientWith(const std::string& token) {
    client::ClientOptions o = OptionsFor(server_);
    o.token = token;
    return client::Client(o);
  }
  std::string Url(const std::string& path) const {
    return "http://127.0.0.1:" + std::to_string(server_.http_port()) + path;
  }

  TempDir data_, files_;
  fs::path token_file_;
  ServerProcess server_;
};

TEST_F(Auth, CallsWithoutTheTokenAreUnauthenticated) {
  client::Client none = ClientWith(""), wrong = ClientWith("s3cret-token-on"), good = ClientWith(kToken);
  const grpc::Status without = StatusOf([&] { none.ListClips(); });
  EXPECT_EQ(without.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_NE(without.error_message().find("Bearer"), std::string::npos);
  const grpc::Status with_wrong = StatusOf([&] { wrong.ListClips(); });
  EXPECT_EQ(with_wrong.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(with_wrong.error_message(), "invalid bearer token");
  EXPECT_EQ(good.ListClips().clips_size(), 2);  // the seeded demo_walk and demo_character.walk
  // Every token in the file works (rotation), whitespace around it ignored.
  EXPECT_EQ(ClientWith(kRotatedToken).ListClips().clips_size(), 2);
  // Another scheme is refused.
  grpc::ClientContext context;
  context.AddMetadata("authorization", std::string("Basic ") + kToken);
  v1::ListClipsResponse clips;
  EXPECT_EQ(v1::AssetService::NewStub(none.channel())->ListClips(&context, {}, &clips).error_code(),
            grpc::StatusCode::UNAUTHENTICATED);
}

TEST_F(Auth, RefusedCallsChangeNothing) {
  client::Client none = ClientWith(""), good = ClientWith(kToken);
  // Unary: the delete never runs.
  EXPECT_EQ(CodeOf([&] { none.DeleteAsset("demo_walk"); }), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(good.GetClip("demo_walk").name(), "demo_walk");
  // Client stream: nothing is imported.
  EXPECT_EQ(CodeOf([&] { none.Import({"arm.bvh", kArmBvh}); }), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(CodeOf([&] { good.GetClip("arm"); }), grpc::StatusCode::NOT_FOUND);
  // Server stream: no frame is sent.
  v1::StreamClipRequest s;
  s.set_clip("demo_walk");
  s.set_duration(0.2);
  int frames = 0;
  EXPECT_EQ(CodeOf([&] { none.StreamClip(s, [&](const v1::PoseFrame&) { return ++frames > 0; }); }),
            grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(frames, 0);
  // With the token all three work.
  EXPECT_EQ(good.Import({"arm.bvh", kArmBvh}).asset().name(), "arm");
  good.StreamClip(s, [&](const v1::PoseFrame&) { return ++frames > 0; });
  EXPECT_GT(frames, 0);
  EXPECT_EQ(good.DeleteAsset("arm").name(), "arm");
}

TEST_F(Auth, HealthStaysOpenAndRefusalsAreCounted) {
  client::Client none = ClientWith("");
  EXPECT_TRUE(none.Healthy());
  EXPECT_EQ(HttpGet(Url("/healthz")).status, 200);
  EXPECT_EQ(HttpGet(Url("/readyz")).status, 200);
  EXPECT_EQ(CodeOf([&] { none.ListAssets(); }), grpc::StatusCode::UNAUTHENTICATED);
  // /metrics is protected like the API.
  const HttpResponse refused = HttpGet(Url("/metrics"));
  EXPECT_EQ(refused.status, 401);
  // The same error body as every other: the code as a number.
  const auto refused_body = nlohmann::json::parse(refused.body, nullptr, false);
  ASSERT_TRUE(refused_body.is_object()) << refused.body;
  EXPECT_EQ(refused_body.value("code", -1), 16) << refused.body;
  EXPECT_FALSE(refused_body.value("message", "").empty()) << refused.body;
  EXPECT_EQ(HttpGet(Url("/metrics"), {"Authorization: Bearer wrong"}).status, 401);
  const HttpResponse metrics = HttpGet(Url("/metrics"), {std::string("Authorization: Bearer ") + kToken});
  ASSERT_EQ(metrics.status, 200);
  EXPECT_NE(
      metrics.body.find(
          "armature_rpc_requests_total{method=\"armature.v1.AssetService/ListAssets\",code=\"UNAUTHENTICATED\"} 1"),
      std::string::npos)
      << metrics.body;
}

// REST rides the same gate: the gateway forwards the authorization header.
TEST_F(Auth, RestCallsNeedTheTokenToo) {
  const HttpResponse refused = HttpGet(Url("/v1/clips"));
  EXPECT_EQ(refused.status, 401);
  const auto body = nlohmann::json::parse(refused.body, nullptr, false);
  ASSERT_FALSE(body.is_discarded()) << refused.body;
  EXPECT_EQ(body["code"], 16);  // UNAUTHENTICATED
  EXPECT_TRUE(body["details"].is_array());
  EXPECT_EQ(HttpGet(Url("/v1/clips"), {"Authorization: Bearer wrong"}).status, 401);
  const HttpResponse ok = HttpGet(Url("/v1/clips"), {std::string("Authorization: Bearer ") + kRotatedToken});
  ASSERT_EQ(ok.status, 200) << ok.body;
  EXPECT_NE(ok.body.find("\"demo_walk\""), std::string::npos) << ok.body;
}

TEST_F(Auth, CliSendsTheToken) {
  auto refused = RunCli(server_.target(), {"list"});
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_NE(refused.err.find("UNAUTHENTICATED"), std::string::npos) << refused.err;
  auto flag = RunCli(server_.target(), {"--token", kToken, "list"});
  EXPECT_EQ(flag.exit_code, 0) << flag.err;
  EXPECT_NE(flag.out.find("demo_walk"), std::string::npos);
  auto env = RunCommand("ARMATURE_TOKEN=" + ShellQuote(kRotatedToken) + " " + ShellQuote(ARMATURE_CLI_BIN) +
                        " --server " + server_.target() + " list");
  EXPECT_EQ(env.exit_code, 0) << env.err;
  auto health = RunCli(server_.target(), {"health"});
  EXPECT_EQ(health.exit_code, 0) << health.err;
}

TEST(AuthConfig, AnEmptyOrMissingTokenFileStopsTheServer) {
  TempDir data, files;
  const fs::path empty = WriteTemp(files, "empty", "\n  \n");
  try {
    ServerProcess server(data.path(), {"--auth-token-file", empty.string()});
    ADD_FAILURE() << "the server started with no token";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("holds no token"), std::string::npos) << e.what();
  }
  try {
    ServerProcess server(data.path(), {"--auth-token-file", (files.path() / "missing").string()});
    ADD_FAILURE() << "the server started with a missing token file";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("auth-token-file"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace armature::testing

namespace armature::testing {
namespace {

// A base64 token ('/', '=') works over gRPC and REST, but a browser cannot
// send it as a WebSocket subprotocol: the server says so at start, by line.
TEST(AuthTokenFile, TokensABrowserCannotSendAreNamedAtStart) {
  TempDir data, files;
  const auto tokens = WriteTemp(files, "tokens", "a1b2c3d4e5f60718293a4b5c6d7e8f90\n\nq9/Zt+Kx0w==\n");
  ServerProcess server(data.path(), {"--auth-token-file", tokens.string()});
  const std::string log = ReadFile(server.log_file());
  EXPECT_NE(log.find(tokens.string() + ":3: this token has characters outside"), std::string::npos) << log;
  EXPECT_NE(log.find("openssl rand -hex 32"), std::string::npos) << log;
  EXPECT_EQ(log.find(tokens.string() + ":1:"), std::string::npos) << "a hex token is safe: " << log;
}

}  // namespace
}  // namespace armature::testing
