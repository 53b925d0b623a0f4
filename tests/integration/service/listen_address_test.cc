// Safe defaults: a bare armature-server listens on 127.0.0.1 only, and warns
// at start when it listens beyond this machine with no token.
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

constexpr char kWarning[] = "beyond this machine with no --auth-token-file";
namespace fs = std::filesystem;

// armature-server with exactly `args` besides free ports and a data dir (the
// harness's ServerProcess always passes --host 127.0.0.1), stopped at the end.
class BareServer {
 public:
  explicit BareServer(const std::string& args) {
    const fs::path ports = dir_.path() / "ports.json", pid = dir_.path() / "pid";
    log_ = dir_.path() / "server.log";
    RunCommand("(" + ShellQuote(ARMATURE_SERVER_BIN) + " --grpc-port 0 --http-port 0 --no-demo --data-dir " +
               ShellQuote((dir_.path() / "data").string()) + " --port-file " + ShellQuote(ports.string()) + " " + args +
               " >" + ShellQuote(log_.string()) + " 2>&1 & echo $! >" + ShellQuote(pid.string()) + ")");
    pid_ = std::stoi(ReadFile(pid));
    for (int i = 0; i < 3000 && !fs::exists(ports); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const auto j = nlohmann::json::parse(ReadFile(ports), nullptr, false);
    if (!j.is_discarded()) grpc_port_ = j.value("grpc", 0), http_port_ = j.value("http", 0);
  }
  ~BareServer() {
    ::kill(pid_, SIGTERM);  // not this process's child (the shell's): wait until it is gone
    for (int i = 0; i < 500 && ::kill(pid_, 0) == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  int grpc_port() const { return grpc_port_; }
  int http_port() const { return http_port_; }
  std::string log() const { return ReadFile(log_); }

 private:
  TempDir dir_;
  fs::path log_;
  pid_t pid_ = -1;
  int grpc_port_ = 0, http_port_ = 0;
};

// "loopback", "any" or the kernel's hex of a listening address: 127.0.0.1 is
// 0100007F, or v4-mapped in tcp6 (gRPC binds dual-stack); any is all zeros.
std::string Kind(const std::string& hex) {
  if (hex == "0100007F" || hex == "0000000000000000FFFF00000100007F" || hex == "00000000000000000000000001000000")
    return "loopback";
  if (hex.find_first_not_of('0') == std::string::npos) return "any";
  return hex;
}

// What kinds of address the sockets listening on `port` have, from /proc/net/tcp and /proc/net/tcp6.
std::set<std::string> ListeningAddresses(int port) {
  std::set<std::string> addresses;
  char port_hex[8];
  std::snprintf(port_hex, sizeof port_hex, "%04X", port);
  for (const char* table : {"/proc/net/tcp", "/proc/net/tcp6"}) {
    std::ifstream in(table);
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
      std::istringstream fields(line);
      std::string slot, local, remote, state;
      fields >> slot >> local >> remote >> state;
      const auto colon = local.find(':');
      if (state == "0A" && colon != std::string::npos && local.substr(colon + 1) == port_hex)  // 0A: LISTEN
        addresses.insert(Kind(local.substr(0, colon)));
    }
  }
  return addresses;
}

TEST(ListenAddress, ABareServerListensOnLoopbackOnly) {
  BareServer server("");
  ASSERT_GT(server.grpc_port(), 0) << server.log();
  for (int port : {server.grpc_port(), server.http_port()}) {
    const std::set<std::string> addresses = ListeningAddresses(port);
    ASSERT_FALSE(addresses.empty()) << "nothing listens on port " << port;
    EXPECT_EQ(addresses, std::set<std::string>{"loopback"}) << "port " << port;
  }
  EXPECT_EQ(server.log().find(kWarning), std::string::npos) << server.log();
}

TEST(ListenAddress, EveryInterfaceWithoutATokenIsWarnedOf) {
  BareServer server("--host 0.0.0.0");
  ASSERT_GT(server.grpc_port(), 0) << server.log();
  EXPECT_EQ(ListeningAddresses(server.grpc_port()), std::set<std::string>{"any"});
  const std::string log = server.log();
  EXPECT_NE(log.find(kWarning), std::string::npos) << log;
  EXPECT_NE(log.find("listening on 0.0.0.0"), std::string::npos) << log;
}

TEST(ListenAddress, EveryInterfaceWithATokenIsNotWarnedOf) {
  TempDir files;
  const auto tokens = WriteTemp(files, "tokens", "a-token\n");
  BareServer server("--host 0.0.0.0 --auth-token-file " + ShellQuote(tokens.string()));
  ASSERT_GT(server.grpc_port(), 0) << server.log();
  EXPECT_EQ(server.log().find(kWarning), std::string::npos) << server.log();
}

}  // namespace
}  // namespace armature::testing
