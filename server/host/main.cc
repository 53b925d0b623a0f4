// armature-server: parse flags, start, wait for SIGTERM/SIGINT, shut down cleanly.
#include <csignal>
#include <cstdio>

#include <spdlog/spdlog.h>

#include "server/host/armature_server.h"
#include "server/host/config.h"
#include "server/host/observability/logging.h"

int main(int argc, char** argv) {
  armature::server::ServerConfig config;
  if (int code = armature::server::ParseConfig(argc, argv, config); code >= 0) return code;
  armature::server::ConfigureLogging(config.log_level, config.log_format);

  // Block the stop signals in every thread; the main thread waits for them.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  std::signal(SIGPIPE, SIG_IGN);

  auto server = armature::server::ArmatureServer::Start(config);
  if (!server.ok()) {
    spdlog::critical("{}", server.status().message());
    return 1;
  }
  int signal = 0;
  sigwait(&stop_signals, &signal);
  spdlog::info("received {}", signal == SIGTERM ? "SIGTERM" : "SIGINT");
  (*server)->Shutdown();
  return 0;
}
