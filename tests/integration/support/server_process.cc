#include "server_process.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>

#include "../../common/spawn_logged.h"

namespace armature::testing {
namespace fs = std::filesystem;

TempDir::TempDir() {
  std::random_device rd;
  path_ = fs::temp_directory_path() / ("armature-test-" + std::to_string(::getpid()) + "-" + std::to_string(rd()));
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string ShellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string SharedData(const std::string& relative) {
  const fs::path p = fs::path(ARMATURE_SHARED_DATA) / relative;
  return fs::exists(p) ? p.string() : "";
}

ServerProcess::ServerProcess(const fs::path& data_dir, std::vector<std::string> extra_args) {
  const fs::path port_file = scratch_.path() / "ports.json";
  log_ = scratch_.path() / "server.log";
  std::vector<std::string> args = {
      ARMATURE_SERVER_BIN, "--grpc-port",     "0",           "--http-port",     "0", "--host", "127.0.0.1",
      "--data-dir",        data_dir.string(), "--port-file", port_file.string()};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  pid_ = SpawnLogged(std::move(args), log_);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    if (fs::exists(port_file)) {
      const auto j = nlohmann::json::parse(ReadFile(port_file), nullptr, false);
      if (!j.is_discarded()) {
        grpc_port_ = j.value("grpc", 0);
        http_port_ = j.value("http", 0);
        return;
      }
    }
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      throw std::runtime_error("armature-server exited while starting:\n" + ReadFile(log_));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  Stop(SIGKILL);
  throw std::runtime_error("armature-server did not start within 60 s:\n" + ReadFile(log_));
}

int ServerProcess::Stop(int signal, double timeout_seconds) {
  if (pid_ <= 0) return -1;
  ::kill(pid_, signal);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_seconds);
  int status = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ::kill(pid_, SIGKILL);
  ::waitpid(pid_, &status, 0);
  pid_ = -1;
  return -1;
}

ServerProcess::~ServerProcess() {
  if (pid_ > 0) Stop(SIGKILL);
}

CommandResult RunCommand(const std::string& command_line) {
  TempDir dir;
  const fs::path out = dir.path() / "out", err = dir.path() / "err";
  const std::string full = command_line + " >" + ShellQuote(out.string()) + " 2>" + ShellQuote(err.string());
  const int status = std::system(full.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = ReadFile(out);
  r.err = ReadFile(err);
  return r;
}

CommandResult RunCli(const std::string& server, const std::vector<std::string>& args) {
  std::string line = ShellQuote(ARMATURE_CLI_BIN) + " --server " + ShellQuote(server);
  for (const auto& a : args) line += " " + ShellQuote(a);
  return RunCommand(line);
}

}  // namespace armature::testing
