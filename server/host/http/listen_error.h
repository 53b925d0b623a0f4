// Why a listener could not bind, said so a user knows what to do.
#pragma once

#include <string>

namespace armature::server {

// "gRPC listener: port 50051 is in use (another armature-server?)" when `port` is taken on `host`,
// else "cannot listen for <listener> on host:port". `listener` is "gRPC" or "HTTP".
std::string ListenError(const std::string& listener, const std::string& host, int port);

}  // namespace armature::server
