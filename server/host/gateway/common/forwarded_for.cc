#include "server/host/gateway/common/forwarded_for.h"

#include <arpa/inet.h>

#include <algorithm>
#include <charconv>
#include <cstring>

namespace armature::server::gateway {
namespace {

std::string_view Trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

// The address as 16 bytes, IPv4 mapped into IPv6 (::ffff:a.b.c.d).
std::optional<std::array<unsigned char, 16>> ParseAddress(std::string_view text, bool* ipv4 = nullptr) {
  const std::string s(text);
  std::array<unsigned char, 16> out{};
  in_addr v4{};
  if (inet_pton(AF_INET, s.c_str(), &v4) == 1) {
    out[10] = out[11] = 0xff;
    std::memcpy(out.data() + 12, &v4, 4);
    if (ipv4) *ipv4 = true;
    return out;
  }
  if (inet_pton(AF_INET6, s.c_str(), out.data()) == 1) {
    if (ipv4) *ipv4 = false;
    return out;
  }
  return std::nullopt;
}

bool InNetwork(const std::array<unsigned char, 16>& a, const Cidr& n) {
  for (int bit = 0; bit < n.prefix_bits; bit += 8) {
    const int bits = std::min(8, n.prefix_bits - bit);
    const unsigned char mask = static_cast<unsigned char>(0xff << (8 - bits));
    if ((a[bit / 8] & mask) != (n.address[bit / 8] & mask)) return false;
  }
  return true;
}

}  // namespace

StatusOr<Cidr> ParseCidr(std::string_view text) {
  const auto bad = [&](const std::string& why) {
    return Status::InvalidArgument("--trust-forwarded-for " + std::string(text) + ": " + why +
                                   "; expected an address or a network, e.g. 10.0.0.0/8 or fd00::/8");
  };
  const size_t slash = text.find('/');
  bool ipv4 = false;
  const auto address = ParseAddress(text.substr(0, slash), &ipv4);
  if (!address) return bad("not an IPv4 or IPv6 address");
  Cidr cidr{*address, 128};
  if (slash != std::string_view::npos) {
    const std::string_view bits = text.substr(slash + 1);
    int prefix = -1;
    const auto [end, ec] = std::from_chars(bits.data(), bits.data() + bits.size(), prefix);
    const int most = ipv4 ? 32 : 128;
    if (ec != std::errc() || end != bits.data() + bits.size() || prefix < 0 || prefix > most)
      return bad("the prefix length must be 0 to " + std::to_string(most));
    cidr.prefix_bits = ipv4 ? 96 + prefix : prefix;
  }
  return cidr;
}

bool TrustedProxies::Contains(std::string_view address) const {
  const auto a = ParseAddress(Trim(address));
  if (!a) return false;
  for (const Cidr& n : networks_)
    if (InNetwork(*a, n)) return true;
  return false;
}

std::string TrustedProxies::ClientOf(const std::string& peer, std::string_view forwarded_for) const {
  if (!Contains(peer)) return peer;
  std::string client = peer;
  while (!forwarded_for.empty()) {
    const size_t comma = forwarded_for.rfind(',');
    const std::string_view item =
        Trim(comma == std::string_view::npos ? forwarded_for : forwarded_for.substr(comma + 1));
    forwarded_for = comma == std::string_view::npos ? std::string_view() : forwarded_for.substr(0, comma);
    if (!ParseAddress(item)) break;  // not an address: nothing left of it can be trusted
    client = std::string(item);
    if (!Contains(item)) break;
  }
  return client;
}

}  // namespace armature::server::gateway
