#include "server/host/auth/bearer_tokens.h"

#include <openssl/crypto.h>
#include <openssl/sha.h>

#include <sstream>

#include "server/assets/file_io.h"
#include "server/rpc/caller_identity.h"

namespace armature::server {
namespace {

std::string_view Trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r\n");
  return s.substr(first, last - first + 1);
}

// RFC 7230's tchar, which a WebSocket subprotocol is made of (RFC 6455 4.1).
bool IsHttpToken(std::string_view s) {
  for (unsigned char c : s)
    if (!std::isalnum(c) && std::string_view("!#$%&'*+-.^_`|~").find(static_cast<char>(c)) == std::string_view::npos)
      return false;
  return true;
}

Status Unauthenticated(std::string message) { return {StatusCode::kUnauthenticated, std::move(message)}; }

}  // namespace

StatusOr<std::shared_ptr<const BearerTokens>> BearerTokens::FromFile(const std::filesystem::path& file) {
  auto text = ReadFile(file);
  if (!text.ok()) return Status::FailedPrecondition("cannot read the auth token file " + file.string());
  return FromText(*text, file.string());
}

StatusOr<std::shared_ptr<const BearerTokens>> BearerTokens::FromText(std::string_view text, std::string_view source) {
  auto tokens = std::shared_ptr<BearerTokens>(new BearerTokens());
  std::istringstream lines{std::string(text)};
  int line_number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++line_number;
    const std::string_view token = Trim(line);
    if (token.empty()) continue;
    if (!IsHttpToken(token)) tokens->not_subprotocol_safe_.push_back(line_number);
    Digest d;
    SHA256(reinterpret_cast<const unsigned char*>(token.data()), token.size(), d.data());
    tokens->accepted_.push_back(d);
  }
  if (tokens->accepted_.empty())
    return Status::FailedPrecondition("the auth token file " + std::string(source) + " holds no token");
  return std::shared_ptr<const BearerTokens>(std::move(tokens));
}

Status BearerTokens::Check(std::string_view authorization) const {
  authorization = Trim(authorization);
  if (authorization.empty())
    return Unauthenticated("missing credentials: send the header 'authorization: Bearer <token>'");
  const std::string_view token = BearerTokenOf(authorization);
  if (token.empty()) return Unauthenticated("the authorization header must be 'Bearer <token>'");
  Digest presented;
  SHA256(reinterpret_cast<const unsigned char*>(token.data()), token.size(), presented.data());
  // Every accepted token is compared, whatever matches, so timing tells nothing.
  int matches = 0;
  for (const Digest& d : accepted_) matches |= CRYPTO_memcmp(d.data(), presented.data(), d.size()) == 0;
  return matches ? Status::Ok() : Unauthenticated("invalid bearer token");
}

}  // namespace armature::server
