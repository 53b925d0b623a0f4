// The client address behind trusted proxies (--trust-forwarded-for CIDR): a
// request from a trusted proxy names its client in X-Forwarded-For; the
// address per-client limits count is the rightmost one in that list that is
// not itself a trusted proxy. Pure: addresses in, address out.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "armature/base/status.h"

namespace armature::server::gateway {

// An IPv4 or IPv6 network. IPv4 addresses are kept as IPv4-mapped IPv6, so
// "10.0.0.0/8" also holds "::ffff:10.1.2.3".
struct Cidr {
  std::array<unsigned char, 16> address{};
  int prefix_bits = 0;  // of the 128
};

// "10.0.0.0/8", "192.168.1.7" (one address), "fd00::/8"; INVALID_ARGUMENT naming `text` otherwise.
StatusOr<Cidr> ParseCidr(std::string_view text);

class TrustedProxies {
 public:
  TrustedProxies() = default;
  explicit TrustedProxies(std::vector<Cidr> networks) : networks_(std::move(networks)) {}

  bool empty() const { return networks_.empty(); }
  bool Contains(std::string_view address) const;
  // The client of a request from `peer` carrying `forwarded_for` (the
  // X-Forwarded-For values joined by commas): `peer` unless it is trusted;
  // else the rightmost untrusted address in the list (the leftmost when all
  // are trusted), or `peer` when the list holds no valid address.
  std::string ClientOf(const std::string& peer, std::string_view forwarded_for) const;

 private:
  std::vector<Cidr> networks_;
};

}  // namespace armature::server::gateway
