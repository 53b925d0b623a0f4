// Files and commands for tests and benchmarks: reading a file whole, the
// shared real-data directory, and running a shell command for its output.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

namespace armature::test_util {

// The file's bytes, or nothing when it cannot be read.
inline std::optional<std::string> ReadFileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

#ifdef ARMATURE_TEST_DIR
// Why three.js cannot run here (the reference scripts in tests/reference), or empty when it can.
inline std::string ThreeJsUnavailable() {
  if (std::system("node --version > /dev/null 2>&1") != 0) return "node is not installed";
  if (!std::filesystem::exists(std::filesystem::path(ARMATURE_TEST_DIR) / "reference/node_modules/three"))
    return "three.js is not installed: run scripts/setup.sh test (npm ci in tests/reference)";
  return "";
}
#endif

#ifdef ARMATURE_SHARED_DATA
// A file of the real test data beside the clone (absent in a user's clone).
inline std::filesystem::path SharedData(const std::string& relative) {
  return std::filesystem::path(ARMATURE_SHARED_DATA) / relative;
}
#endif

// Runs a shell command; its stdout, or nothing when it fails.
inline std::optional<std::string> RunCommand(const std::string& command) {
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return std::nullopt;
  std::string out;
  char buffer[65536];
  for (size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) out.append(buffer, n);
  return pclose(pipe) == 0 ? std::optional(out) : std::nullopt;
}

}  // namespace armature::test_util
