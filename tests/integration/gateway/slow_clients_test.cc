// Slow clients on the HTTP port (slowloris): a request head has one deadline
// in all (--http-head-timeout), not a timeout per byte, and one address holds
// at most --http-max-connections-per-address connections, so a few hundred
// connections that each send a header byte now and then leave /healthz and
// REST answering, and are all closed in the end; over TLS the handshake is
// part of the head. Loopback only: the slow
// connections come from 127.0.0.2, the probes from 127.0.0.1.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <httplib.h>

#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

using Clock = std::chrono::steady_clock;

// A TCP connection from `source` to 127.0.0.1:`port`, or -1.
int ConnectFrom(const char* source, int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in from{}, to{};
  from.sin_family = to.sin_family = AF_INET;
  inet_pton(AF_INET, source, &from.sin_addr);
  inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
  to.sin_port = htons(static_cast<uint16_t>(port));
  if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&from), sizeof(from)) != 0 ||
      ::connect(fd, reinterpret_cast<sockaddr*>(&to), sizeof(to)) != 0) {
    if (fd >= 0) ::close(fd);
    return -1;
  }
  return fd;
}

// A slow client: its connection and what the server sent it.
struct SlowConnection {
  int fd = -1;
  std::string received;
  bool closed = false;  // by the server (end of stream or reset)

  // Reads what is there without waiting.
  void Poll() {
    char buf[4096];
    while (!closed) {
      const ssize_t n = ::recv(fd, buf, sizeof(buf), MSG_DONTWAIT);
      if (n > 0) {
        received.append(buf, static_cast<size_t>(n));
      } else {
        closed = n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK);
        return;
      }
    }
  }
};

// One header byte at a time: a request head that never ends.
constexpr char kSlowHead[] =
    "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa";

TEST(SlowClients, SlowHeadsAreCutAndOneAddressHoldsAFew) {
  constexpr int kConnections = 300, kPerAddress = 64;
  TempDir data;
  ServerProcess server(data.path(),
                       {"--http-head-timeout", "3", "--http-max-connections-per-address", std::to_string(kPerAddress)});
  std::vector<SlowConnection> slow(kConnections);
  // In a burst: the listen backlog holds them until they are accepted.
  for (auto& c : slow) {
    c.fd = ConnectFrom("127.0.0.2", server.http_port());
    ASSERT_GE(c.fd, 0) << "could not connect from 127.0.0.2";
    (void)!::send(c.fd, kSlowHead, 1, MSG_NOSIGNAL);
  }
  // Those over the cap are answered 429 at once.
  auto refused = [&] {
    int n = 0;
    for (auto& c : slow) {
      c.Poll();
      n += c.received.rfind("HTTP/1.1 429", 0) == 0 && c.closed;
    }
    return n;
  };
  EXPECT_TRUE(WaitFor([&] { return refused() == kConnections - kPerAddress; }, 20)) << refused() << " refused";
  for (const auto& c : slow)
    if (c.closed) {
      EXPECT_NE(c.received.find("--http-max-connections-per-address (64)"), std::string::npos) << c.received;
      break;
    }

  // The rest send a header byte a second for 7 s, more than twice the head
  // timeout; meanwhile each probe from another address is answered within 1 s.
  httplib::Client probe("127.0.0.1", server.http_port());
  probe.set_connection_timeout(1);
  probe.set_read_timeout(1);
  int probes = 0, failed_probes = 0;
  std::string last_failure;
  const auto until = Clock::now() + std::chrono::seconds(7);
  for (size_t sent = 0; Clock::now() < until; ++sent) {
    for (auto& c : slow) {
      c.Poll();
      if (!c.closed && sent + 1 < sizeof(kSlowHead) - 1) (void)!::send(c.fd, &kSlowHead[sent + 1], 1, MSG_NOSIGNAL);
    }
    for (const char* path : {"/healthz", "/v1/clips"}) {
      ++probes;
      const auto r = probe.Get(path);
      if (!r || r->status != 200) {
        ++failed_probes;
        last_failure = std::string(path) + ": " + (r ? std::to_string(r->status) : httplib::to_string(r.error()));
      }
    }
    std::this_thread::sleep_for(std::chrono::seconds(1));
  }
  EXPECT_EQ(failed_probes, 0) << "of " << probes << " probes; the last: " << last_failure;

  // The slow ones were told why and closed.
  int still_open = 0, timed_out = 0;
  for (auto& c : slow) {
    pollfd p{c.fd, POLLIN, 0};
    if (!c.closed && ::poll(&p, 1, 2000) > 0) c.Poll();
    still_open += !c.closed;
    if (c.received.rfind("HTTP/1.1 408", 0) == 0) {
      ++timed_out;
      EXPECT_NE(c.received.find("--http-head-timeout (3 s)"), std::string::npos) << c.received;
    }
    ::close(c.fd);
  }
  EXPECT_EQ(still_open, 0);
  EXPECT_EQ(timed_out, kPerAddress);
}

// Over TLS the handshake is part of the head: a ClientHello that comes a
// byte at a time is cut at the same deadline.
TEST(SlowClients, ASlowTlsHandshakeIsCutAtTheHeadDeadline) {
  TempDir data, files;
  const auto cert = files.path() / "server.crt", key = files.path() / "server.key";
  const CommandResult made =
      RunCommand("openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=localhost -keyout " +
                 ShellQuote(key.string()) + " -out " + ShellQuote(cert.string()));
  ASSERT_EQ(made.exit_code, 0) << made.err;
  ServerProcess server(data.path(),
                       {"--tls-cert", cert.string(), "--tls-key", key.string(), "--http-head-timeout", "2"});
  SlowConnection c;
  c.fd = ConnectFrom("127.0.0.2", server.http_port());
  ASSERT_GE(c.fd, 0);
  // A handshake record's header announcing 512 bytes, then its body two bytes a second.
  const std::string record = std::string("\x16\x03\x01\x02\x00", 5) + std::string(512, '\0');
  const auto start = Clock::now();
  for (size_t i = 0; !c.closed && i < record.size() && Clock::now() - start < std::chrono::seconds(12); ++i) {
    (void)!::send(c.fd, &record[i], 1, MSG_NOSIGNAL);
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    c.Poll();
  }
  EXPECT_TRUE(c.closed) << "the server still held the handshake after 12 s";
  ::close(c.fd);
}

// A head that arrives whole, however slowly it started, is served: the
// deadline is for the head, not for the connection or what follows it.
TEST(SlowClients, KeepAliveRequestsEachGetTheirOwnDeadline) {
  TempDir data;
  ServerProcess server(data.path(), {"--http-head-timeout", "2"});
  httplib::Client client("127.0.0.1", server.http_port());
  client.set_keep_alive(true);
  for (int i = 0; i < 3; ++i) {
    const auto r = client.Get("/healthz");
    ASSERT_TRUE(r) << "request " << i;
    EXPECT_EQ(r->status, 200);
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // idle past most of a head timeout
  }
}

}  // namespace
}  // namespace armature::testing
