// Test harness: a real armature-server process on free ports, and the CLI run
// as a real process.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace armature::testing {

// A fresh temporary directory, removed with the object.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

class ServerProcess {
 public:
  // Starts armature-server with --grpc-port 0 --http-port 0 and waits until it serves.
  explicit ServerProcess(const std::filesystem::path& data_dir, std::vector<std::string> extra_args = {});
  ~ServerProcess();

  std::string target() const { return "127.0.0.1:" + std::to_string(grpc_port_); }
  int grpc_port() const { return grpc_port_; }
  int http_port() const { return http_port_; }
  pid_t pid() const { return pid_; }
  const std::filesystem::path& log_file() const { return log_; }

  // Sends `signal` and waits (up to `timeout_seconds`); returns the exit code,
  // or -1 if it did not exit in time (then it is killed).
  int Stop(int signal, double timeout_seconds = 15);
  bool running() const { return pid_ > 0; }

 private:
  pid_t pid_ = -1;
  int grpc_port_ = 0;
  int http_port_ = 0;
  std::filesystem::path log_;
  TempDir scratch_;
};

struct CommandResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// Runs the `armature` CLI with `args` against `server` ("host:port").
CommandResult RunCli(const std::string& server, const std::vector<std::string>& args);
// Runs any command line through /bin/sh.
CommandResult RunCommand(const std::string& command_line);

std::string ReadFile(const std::filesystem::path& path);
std::string ShellQuote(const std::string& s);
// The shared real data dir, or "" when it is not there (a user's clone).
std::string SharedData(const std::string& relative);

}  // namespace armature::testing
