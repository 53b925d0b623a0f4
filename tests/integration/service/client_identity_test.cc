// Who per-client limits count: a bearer token names a client only when the
// auth gate verified it (however the scheme is spelled), and --max-streams
// caps the streams of all clients together.
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "armature/v1/poses.grpc.pb.h"
#include "engine/testing/test_files.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

// One StreamClip call sent with `authorization` (looping: it lasts until closed).
class AuthorizedStream {
 public:
  AuthorizedStream(v1::PoseService::Stub& stub, const std::string& authorization) {
    context_.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
    if (!authorization.empty()) context_.AddMetadata("authorization", authorization);
    v1::StreamClipRequest r;
    r.set_clip("arm");
    r.set_fps(10);
    r.set_loop(true);
    reader_ = stub.StreamClip(&context_, r);
    v1::PoseFrame first;
    open_ = reader_->Read(&first);
  }
  ~AuthorizedStream() { (void)Close(); }
  bool open() const { return open_; }
  grpc::Status Close() {
    if (!reader_) return status_;
    if (open_) context_.TryCancel();
    for (v1::PoseFrame rest; reader_->Read(&rest);) {}
    status_ = reader_->Finish();
    reader_.reset();
    return status_;
  }

 private:
  grpc::ClientContext context_;
  std::unique_ptr<grpc::ClientReader<v1::PoseFrame>> reader_;
  bool open_ = false;
  grpc::Status status_;
};

std::unique_ptr<v1::PoseService::Stub> PoseStub(const ServerProcess& server) {
  return v1::PoseService::NewStub(grpc::CreateChannel(server.target(), grpc::InsecureChannelCredentials()));
}

// The refusal of `stream`, which must not have opened.
std::string RefusalOf(AuthorizedStream& stream) {
  EXPECT_FALSE(stream.open());
  const grpc::Status status = stream.Close();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
  return status.error_message();
}

// Without a token file nobody checks tokens: a made-up one per call must not
// make each call a new client.
TEST(ClientIdentity, UncheckedTokensDoNotMakeNewClients) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--max-streams-per-client", "2"});
  client::Client(OptionsFor(server)).Import({"arm.bvh", kArmBvh});
  auto stub = PoseStub(server);
  std::vector<std::unique_ptr<AuthorizedStream>> open;
  for (const char* token : {"Bearer made-up-1", "Bearer made-up-2"}) {
    open.push_back(std::make_unique<AuthorizedStream>(*stub, token));
    ASSERT_TRUE(open.back()->open()) << token << ": " << open.back()->Close().error_message();
  }
  AuthorizedStream third(*stub, "Bearer made-up-3");
  EXPECT_NE(RefusalOf(third).find("--max-streams-per-client (2)"), std::string::npos);
}

// With a token file, one token is one client whatever the scheme's case or
// the spaces after it.
TEST(ClientIdentity, OneTokenIsOneClientHoweverTheSchemeIsSpelled) {
  TempDir data, files;
  const auto token_file = WriteTemp(files, "tokens", "tok-a\ntok-b\n");
  ServerProcess server(data.path(),
                       {"--no-demo", "--auth-token-file", token_file.string(), "--max-streams-per-client", "1"});
  client::ClientOptions options = OptionsFor(server);
  options.token = "tok-a";
  client::Client(options).Import({"arm.bvh", kArmBvh});
  auto stub = PoseStub(server);
  AuthorizedStream first(*stub, "Bearer tok-a");
  ASSERT_TRUE(first.open()) << first.Close().error_message();
  for (const char* spelling : {"bearer tok-a", "BEARER tok-a", "Bearer  tok-a", "Bearer tok-a "}) {
    AuthorizedStream again(*stub, spelling);
    EXPECT_NE(RefusalOf(again).find("--max-streams-per-client (1)"), std::string::npos) << spelling;
  }
  // Another accepted token is another client.
  AuthorizedStream other(*stub, "Bearer tok-b");
  EXPECT_TRUE(other.open()) << other.Close().error_message();
}

// --max-streams bounds every client's streams together.
TEST(ClientIdentity, StreamsOfAllClientsHaveACap) {
  TempDir data, files;
  const auto token_file = WriteTemp(files, "tokens", "tok-a\ntok-b\ntok-c\n");
  ServerProcess server(data.path(), {"--no-demo", "--auth-token-file", token_file.string(), "--max-streams", "2"});
  client::ClientOptions options = OptionsFor(server);
  options.token = "tok-a";
  client::Client(options).Import({"arm.bvh", kArmBvh});
  auto stub = PoseStub(server);
  AuthorizedStream a(*stub, "Bearer tok-a");
  AuthorizedStream b(*stub, "Bearer tok-b");
  ASSERT_TRUE(a.open() && b.open());
  AuthorizedStream c(*stub, "Bearer tok-c");
  const std::string message = RefusalOf(c);
  EXPECT_NE(message.find("--max-streams (2)"), std::string::npos) << message;
  EXPECT_NE(message.find("StreamClip"), std::string::npos) << message;
  a.Close();
  // The place comes back once the server has seen the cancellation.
  EXPECT_TRUE(WaitFor([&] { return AuthorizedStream(*stub, "Bearer tok-c").open(); }, 20));
}

}  // namespace
}  // namespace armature::testing
