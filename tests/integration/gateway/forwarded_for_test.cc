// --trust-forwarded-for: behind a trusted proxy, per-client limits count the
// client its X-Forwarded-For names; from anyone else the header is ignored.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "engine/testing/test_files.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

// A REST stream (StreamClip as SSE) opened from `source` with an
// X-Forwarded-For header; the connection stays open while the object lives.
class ForwardedStream {
 public:
  ForwardedStream(int port, const char* source, const std::string& forwarded_for) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in from{}, to{};
    from.sin_family = to.sin_family = AF_INET;
    inet_pton(AF_INET, source, &from.sin_addr);
    inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
    to.sin_port = htons(static_cast<uint16_t>(port));
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&from), sizeof(from)) != 0 ||
        ::connect(fd_, reinterpret_cast<sockaddr*>(&to), sizeof(to)) != 0)
      return;
    const std::string request =
        "GET /v1/clips/arm:stream?loop=true&fps=10 HTTP/1.1\r\nHost: 127.0.0.1\r\n"
        "X-Forwarded-For: " +
        forwarded_for + "\r\n\r\n";
    (void)!::send(fd_, request.data(), request.size(), MSG_NOSIGNAL);
    // Until the first frame, or the refusal's body.
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (!admitted() && received_.find("\"message\"") == std::string::npos &&
           std::chrono::steady_clock::now() < until) {
      pollfd p{fd_, POLLIN, 0};
      char buf[4096];
      if (::poll(&p, 1, 200) <= 0) continue;
      const ssize_t n = ::recv(fd_, buf, sizeof(buf), 0);
      if (n <= 0) break;
      received_.append(buf, static_cast<size_t>(n));
    }
  }
  ~ForwardedStream() { ::close(fd_); }
  bool admitted() const { return received_.find("data: ") != std::string::npos; }
  const std::string& received() const { return received_; }

 private:
  int fd_ = -1;
  std::string received_;
};

TEST(ForwardedFor, ATrustedProxysClientsCountApart) {
  TempDir data;
  ServerProcess server(data.path(),
                       {"--no-demo", "--max-streams-per-client", "1", "--trust-forwarded-for", "127.0.0.1/32"});
  client::Client(OptionsFor(server)).Import({"arm.bvh", kArmBvh});
  const int port = server.http_port();

  // Through the trusted proxy (127.0.0.1): one stream each for two clients.
  ForwardedStream first(port, "127.0.0.1", "203.0.113.1");
  ASSERT_TRUE(first.admitted()) << first.received();
  ForwardedStream second(port, "127.0.0.1", "198.51.100.7, 203.0.113.2");
  EXPECT_TRUE(second.admitted()) << "another client behind the proxy: " << second.received();
  // The first client again, behind a chain of trusted hops: over its limit.
  ForwardedStream again(port, "127.0.0.1", "203.0.113.1, 127.0.0.1");
  EXPECT_FALSE(again.admitted());
  EXPECT_NE(again.received().find("--max-streams-per-client"), std::string::npos) << again.received();

  // From an address that is not a trusted proxy the header counts for nothing.
  ForwardedStream direct(port, "127.0.0.2", "192.0.2.1");
  ASSERT_TRUE(direct.admitted()) << direct.received();
  ForwardedStream spoofed(port, "127.0.0.2", "192.0.2.2");
  EXPECT_FALSE(spoofed.admitted());
  EXPECT_NE(spoofed.received().find("--max-streams-per-client"), std::string::npos) << spoofed.received();
}

TEST(ForwardedFor, AMalformedNetworkStopsTheServer) {
  TempDir data;
  const CommandResult r =
      RunCommand(std::string(ARMATURE_SERVER_BIN) + " --trust-forwarded-for 10.0.0.0/33 --data-dir " +
                 ShellQuote(data.path().string()));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE((r.out + r.err).find("10.0.0.0/33"), std::string::npos) << r.out << r.err;
  EXPECT_NE((r.out + r.err).find("prefix length must be 0 to 32"), std::string::npos) << r.out << r.err;
}

}  // namespace
}  // namespace armature::testing
