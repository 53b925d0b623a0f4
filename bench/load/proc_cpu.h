// CPU time of a process from /proc/<pid>/stat (utime + stime), to report a
// server's CPU use over a measurement window.
#pragma once

#include <unistd.h>

#include <fstream>
#include <sstream>
#include <string>

namespace armature_load {

// Seconds of CPU (user + system) the process has used; -1 when unreadable.
inline double ProcessCpuSeconds(int pid) {
  std::ifstream in(pid > 0 ? "/proc/" + std::to_string(pid) + "/stat" : "/proc/self/stat");
  std::string stat;
  if (!std::getline(in, stat)) return -1;
  // The command name (field 2) is in parentheses and may hold spaces: fields
  // are counted from the last ')'. utime and stime are fields 14 and 15.
  const auto close = stat.rfind(')');
  if (close == std::string::npos) return -1;
  std::istringstream fields(stat.substr(close + 2));
  std::string field;
  long long utime = 0, stime = 0;
  for (int k = 3; k <= 15 && fields >> field; ++k) {
    if (k == 14) utime = std::stoll(field);
    if (k == 15) stime = std::stoll(field);
  }
  return static_cast<double>(utime + stime) / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

}  // namespace armature_load
