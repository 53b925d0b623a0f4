// A child process for tests: `args` run with stdout and stderr to `log`.
// Header-only: the integration harness and the server unit tests both
// start processes (armature-server, s3rver).
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

namespace armature::testing {

// `args[0]` is a path, or a program looked up on PATH when `search_path`.
// Returns the child's pid (-1 if fork failed); a failed exec exits 127.
inline pid_t SpawnLogged(std::vector<std::string> args, const std::filesystem::path& log, bool search_path = false) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    if (search_path)
      ::execvp(argv[0], argv.data());
    else
      ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

}  // namespace armature::testing
