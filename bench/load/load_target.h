// What armature-load may aim at: a server on this machine only (127.0.0.0/8,
// localhost, [::1]), so a load run can never hammer someone else's server.
#pragma once

#include <string>

namespace armature_load {

// True for "127.a.b.c:port", "localhost:port" and "[::1]:port" (an optional
// "ipv4:"/"ipv6:" scheme allowed); the port must be 1..65535.
inline bool IsLoopbackTarget(std::string target) {
  for (const char* scheme : {"ipv4:", "ipv6:", "dns:"})
    if (target.rfind(scheme, 0) == 0) target = target.substr(std::string(scheme).size());
  std::string host, port;
  if (!target.empty() && target[0] == '[') {
    const auto close = target.find(']');
    if (close == std::string::npos || close + 1 >= target.size() || target[close + 1] != ':') return false;
    host = target.substr(1, close - 1);
    port = target.substr(close + 2);
  } else {
    const auto colon = target.rfind(':');
    if (colon == std::string::npos) return false;
    host = target.substr(0, colon);
    port = target.substr(colon + 1);
  }
  if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos) return false;
  if (const int p = std::stoi(port); p < 1 || p > 65535) return false;
  if (host == "localhost" || host == "::1") return true;
  // Dotted IPv4 with four octets 0..255, the first 127.
  int octets = 0;
  size_t start = 0;
  while (start <= host.size()) {
    const auto dot = host.find('.', start);
    const std::string part = host.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (part.empty() || part.size() > 3 || part.find_first_not_of("0123456789") != std::string::npos) return false;
    const int v = std::stoi(part);
    if (v > 255 || (octets == 0 && v != 127)) return false;
    ++octets;
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return octets == 4;
}

}  // namespace armature_load
