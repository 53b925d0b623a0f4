// The bearer tokens a server accepts (--auth-token-file), checked in
// constant time. Used by the gRPC auth gate and by HTTP routes that are
// not gRPC calls (/metrics).
#pragma once

#include <array>
#include <filesystem>
#include <memory>
#include <string_view>
#include <vector>

#include "armature/base/status.h"

namespace armature::server {

class BearerTokens {
 public:
  // One token per non-empty line (surrounding whitespace ignored), so a new
  // token can be added before the old one is removed. FAILED_PRECONDITION
  // when the file cannot be read or holds no token.
  static StatusOr<std::shared_ptr<const BearerTokens>> FromFile(const std::filesystem::path& file);
  static StatusOr<std::shared_ptr<const BearerTokens>> FromText(std::string_view text, std::string_view source);

  // `authorization` is the header or metadata value, "Bearer <token>".
  // OK, or UNAUTHENTICATED saying what is missing or wrong (never the token).
  Status Check(std::string_view authorization) const;

  // The file's line numbers (from 1) of tokens with a character outside
  // HTTP's token characters ('/', '=', ...): a browser cannot send those in a
  // WebSocket subprotocol ("bearer.<token>"), so the server warns at start.
  const std::vector<int>& lines_browsers_cannot_send() const { return not_subprotocol_safe_; }

 private:
  using Digest = std::array<unsigned char, 32>;  // SHA-256: equal-length, so the comparison leaks no length
  std::vector<Digest> accepted_;
  std::vector<int> not_subprotocol_safe_;
};

}  // namespace armature::server
