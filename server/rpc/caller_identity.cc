#include "server/rpc/caller_identity.h"

namespace armature::server {

std::string AuthorizationOf(const grpc::ServerContextBase& context) {
  const auto& metadata = context.client_metadata();
  const auto it = metadata.find("authorization");
  return it == metadata.end() ? std::string() : std::string(it->second.data(), it->second.size());
}

// "ipv4:10.0.0.7:51234" → "peer:ipv4:10.0.0.7"; "unix:/run/a.sock" has no port and stays whole.
std::string ClientIdentityOf(const grpc::ServerContextBase& context) {
  if (std::string auth = AuthorizationOf(context); !auth.empty()) return "token:" + auth;
  std::string peer = context.peer();
  // The REST gateway calls in-process for every HTTP client: it names the
  // real one in metadata that only the in-process channel can carry.
  // (gRPC names the in-process peer "unknown"; network peers are ipv4:, ipv6: or unix:).
  if (peer == "unknown" || peer.rfind("inproc", 0) == 0) {
    const auto& metadata = context.client_metadata();
    if (auto it = metadata.find(kRestPeerMetadata); it != metadata.end())
      return "rest:" + std::string(it->second.data(), it->second.size());
  }
  const size_t colon = peer.rfind(':');
  if (colon != std::string::npos && colon > peer.find(':')) peer.resize(colon);
  return "peer:" + peer;
}

}  // namespace armature::server
