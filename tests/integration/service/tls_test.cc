// --tls-cert / --tls-key: gRPC and HTTP over TLS, with a self-signed
// certificate the test makes with the openssl command-line tool.
#include <gtest/gtest.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/http_get.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {
namespace fs = std::filesystem;

// A self-signed certificate for localhost and 127.0.0.1, and its key.
struct KeyPair {
  fs::path cert, key;
};

KeyPair MakeSelfSigned(const TempDir& dir, const std::string& stem) {
  KeyPair kp{dir.path() / (stem + ".crt"), dir.path() / (stem + ".key")};
  const CommandResult r = RunCommand(
      "openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=localhost"
      " -addext subjectAltName=DNS:localhost,IP:127.0.0.1 -keyout " +
      ShellQuote(kp.key.string()) + " -out " + ShellQuote(kp.cert.string()));
  if (r.exit_code != 0) throw std::runtime_error("openssl failed: " + r.err);
  return kp;
}

class Tls : public ::testing::Test {
 protected:
  Tls()
      : kp_(MakeSelfSigned(files_, "server")),
        server_(data_.path(), {"--tls-cert", kp_.cert.string(), "--tls-key", kp_.key.string()}) {}

  TempDir data_, files_;
  KeyPair kp_;
  ServerProcess server_;
};

TEST_F(Tls, GrpcOverTlsTrustingTheCertificate) {
  client::ClientOptions o = OptionsFor(server_);
  o.ca_file = kp_.cert.string();
  client::Client client(o);
  EXPECT_TRUE(client.Healthy());
  EXPECT_EQ(client.GetClip("demo_walk").name(), "demo_walk");
  // A plaintext client gets no answer.
  client::ClientOptions plain = OptionsFor(server_);
  plain.timeout = std::chrono::seconds(20);  // the refusal is prompt; the bound only guards a hang
  EXPECT_EQ(CodeOf([&] { client::Client(plain).ListClips(); }), grpc::StatusCode::UNAVAILABLE);
  // Nor does one trusting another certificate.
  client::ClientOptions other = o;
  other.ca_file = MakeSelfSigned(files_, "other").cert.string();
  other.timeout = std::chrono::seconds(20);
  EXPECT_EQ(CodeOf([&] { client::Client(other).ListClips(); }), grpc::StatusCode::UNAVAILABLE);
  // The CLI's --ca-file.
  const auto cli = RunCli(server_.target(), {"--ca-file", kp_.cert.string(), "list"});
  EXPECT_EQ(cli.exit_code, 0) << cli.err;
  EXPECT_NE(cli.out.find("demo_walk"), std::string::npos);
}

TEST_F(Tls, HttpsOnTheHttpPort) {
  const std::string port = std::to_string(server_.http_port());
  const HttpResponse health = HttpGet("https://localhost:" + port + "/healthz", {}, kp_.cert.string());
  EXPECT_EQ(health.status, 200) << health.error;
  EXPECT_NE(health.body.find("ok"), std::string::npos);
  EXPECT_EQ(HttpGet("https://127.0.0.1:" + port + "/metrics", {}, kp_.cert.string()).status, 200);
  EXPECT_EQ(HttpGet("http://127.0.0.1:" + port + "/healthz").status, 0) << "plain HTTP must not be served";
}

TEST(TlsConfig, BadKeyFilesStopTheServerNamingTheFile) {
  TempDir data, files;
  const KeyPair a = MakeSelfSigned(files, "a"), b = MakeSelfSigned(files, "b");
  try {
    ServerProcess server(data.path(), {"--tls-cert", a.cert.string(), "--tls-key", b.key.string()});
    ADD_FAILURE() << "started with a key of another certificate";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("does not belong to --tls-cert"), std::string::npos) << e.what();
  }
  const fs::path junk = WriteTemp(files, "junk.pem", "not a certificate");
  try {
    ServerProcess server(data.path(), {"--tls-cert", junk.string(), "--tls-key", a.key.string()});
    ADD_FAILURE() << "started with a junk certificate";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("junk.pem is not a PEM certificate"), std::string::npos) << e.what();
  }
  try {
    ServerProcess server(data.path(), {"--tls-cert", a.cert.string()});
    ADD_FAILURE() << "started with a certificate and no key";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("--tls-key"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace armature::testing
