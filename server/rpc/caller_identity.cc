#include "server/rpc/caller_identity.h"

namespace armature::server {
namespace {

constexpr std::string_view kWhitespace = " \t\r\n";

std::string_view Trim(std::string_view s) {
  const auto first = s.find_first_not_of(kWhitespace);
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(kWhitespace) - first + 1);
}

}  // namespace

std::string AuthorizationOf(const grpc::ServerContextBase& context) {
  const auto& metadata = context.client_metadata();
  const auto it = metadata.find("authorization");
  return it == metadata.end() ? std::string() : std::string(it->second.data(), it->second.size());
}

std::string_view BearerTokenOf(std::string_view authorization) {
  authorization = Trim(authorization);
  constexpr std::string_view kScheme = "bearer";
  if (authorization.size() <= kScheme.size() ||
      (authorization[kScheme.size()] != ' ' && authorization[kScheme.size()] != '\t'))
    return {};
  for (size_t i = 0; i < kScheme.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(authorization[i])) != kScheme[i]) return {};
  return Trim(authorization.substr(kScheme.size()));
}

// "ipv4:10.0.0.7:51234" → "peer:ipv4:10.0.0.7"; "unix:/run/a.sock" has no port and stays whole.
std::string ClientIdentityOf(const grpc::ServerContextBase& context, bool tokens_verified) {
  if (tokens_verified) {
    if (std::string_view token = BearerTokenOf(AuthorizationOf(context)); !token.empty())
      return "token:" + std::string(token);
  }
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
