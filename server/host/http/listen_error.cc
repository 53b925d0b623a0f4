#include "server/host/http/listen_error.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>

namespace armature::server {
namespace {
// Binds a probe socket (SO_REUSEADDR only, like the listeners) to learn whether the port is taken.
bool PortInUse(const std::string& host, int port) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* found = nullptr;
  const std::string service = std::to_string(port);
  if (::getaddrinfo(host.empty() ? nullptr : host.c_str(), service.c_str(), &hints, &found) != 0) return false;
  bool in_use = false;
  for (addrinfo* a = found; a && !in_use; a = a->ai_next) {
    const int fd = ::socket(a->ai_family, a->ai_socktype, a->ai_protocol);
    if (fd < 0) continue;
    const int yes = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
    if (::bind(fd, a->ai_addr, a->ai_addrlen) != 0 && errno == EADDRINUSE) in_use = true;
    ::close(fd);
  }
  ::freeaddrinfo(found);
  return in_use;
}
}  // namespace

std::string ListenError(const std::string& listener, const std::string& host, int port) {
  if (port > 0 && PortInUse(host, port))
    return listener + " listener: port " + std::to_string(port) + " is in use (another armature-server?)";
  return "cannot listen for " + listener + " on " + host + ":" + std::to_string(port);
}

}  // namespace armature::server
