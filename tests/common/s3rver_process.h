// A real S3-compatible server for tests: s3rver (npm, tests/store) on a
// loopback port, its objects in a directory, so a restart on the same
// directory and port finds them again. Header-only: the server unit tests
// and the integration tests both start it. s3rver accepts the access key
// S3RVER only; it checks that the key exists, not the SigV4 signature.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "spawn_logged.h"

namespace armature::testing {

class S3rverProcess {
 public:
  // Starts s3rver on `port` (0: a free one) over `dir` (empty: a fresh
  // temporary one, removed with the object), creating `buckets`.
  explicit S3rverProcess(std::vector<std::string> buckets, int port = 0, std::filesystem::path dir = {})
      : buckets_(std::move(buckets)) {
    std::string pattern = (std::filesystem::temp_directory_path() / "armature-s3rver-XXXXXX").string();
    if (!::mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
    scratch_ = pattern;
    dir_ = dir.empty() ? scratch_ / "objects" : dir;
    Start(port);
  }
  ~S3rverProcess() {
    Stop(SIGTERM);
    std::error_code ec;
    std::filesystem::remove_all(scratch_, ec);
  }
  S3rverProcess(const S3rverProcess&) = delete;
  S3rverProcess& operator=(const S3rverProcess&) = delete;

  int port() const { return port_; }
  const std::filesystem::path& dir() const { return dir_; }
  // --store's value for `bucket` and `prefix`.
  std::string Url(const std::string& bucket, const std::string& prefix = "") const {
    return "s3://127.0.0.1:" + std::to_string(port_) + "/" + bucket + (prefix.empty() ? "" : "/" + prefix);
  }
  // Stops it (the bucket "gone"); Restart brings it back on the same port and objects.
  void Stop(int signal = SIGKILL) {
    if (pid_ <= 0) return;
    ::kill(pid_, signal);
    int status = 0;
    for (int i = 0; i < 100 && ::waitpid(pid_, &status, WNOHANG) == 0; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (::waitpid(pid_, &status, WNOHANG) == 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, &status, 0);
    }
    pid_ = -1;
  }
  void Restart() {
    Stop();
    Start(port_);
  }

  // tests/store: s3rver.mjs, its node_modules from `make test-deps`.
  static std::filesystem::path ToolDir() { return std::filesystem::path(ARMATURE_TEST_DIR) / "store"; }

 private:
  void Start(int port) {
    const std::filesystem::path port_file = scratch_ / "port.json", log = scratch_ / "s3rver.log";
    std::filesystem::remove(port_file);
    if (!std::filesystem::exists(ToolDir() / "node_modules" / "s3rver"))
      throw std::runtime_error("s3rver is not installed in " + ToolDir().string() + ": run make test-deps");
    // The legacy provider: s3rver's continuation tokens use DES, which Node 17+ (OpenSSL 3) leaves out.
    std::vector<std::string> args = {
        "node",   "--openssl-legacy-provider", (ToolDir() / "s3rver.mjs").string(), dir_.string(), port_file.string(),
        "--port", std::to_string(port)};
    args.insert(args.end(), buckets_.begin(), buckets_.end());
    pid_ = SpawnLogged(std::move(args), log, /*search_path=*/true);
    for (int i = 0; i < 1500; ++i) {  // 30 s
      std::ifstream in(port_file);
      std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      if (const size_t colon = text.find(':'); colon != std::string::npos) {
        port_ = std::atoi(text.c_str() + colon + 1);
        return;
      }
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        std::ifstream l(log);
        std::stringstream s;
        s << l.rdbuf();
        throw std::runtime_error("s3rver exited while starting:\n" + s.str());
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    throw std::runtime_error("s3rver did not start within 30 s");
  }

  std::vector<std::string> buckets_;
  std::filesystem::path scratch_, dir_;
  pid_t pid_ = -1;
  int port_ = 0;
};

}  // namespace armature::testing
