#include "server/assets/bucket/store_url.h"

#include <cctype>
#include <charconv>

namespace armature::server {
namespace {

// S3's bucket naming rules: 3 to 63 lowercase letters, digits, '.' and '-',
// starting and ending with a letter or digit.
bool IsBucketName(std::string_view name) {
  if (name.size() < 3 || name.size() > 63) return false;
  for (char c : name)
    if (!(std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '.' ||
          c == '-'))
      return false;
  return std::isalnum(static_cast<unsigned char>(name.front())) &&
         std::isalnum(static_cast<unsigned char>(name.back()));
}

std::string FoldPrefix(std::string_view path) {
  std::string out;
  size_t start = 0;
  while (start < path.size()) {
    size_t end = path.find('/', start);
    if (end == std::string_view::npos) end = path.size();
    if (end > start) out.append(path.substr(start, end - start)).push_back('/');
    start = end + 1;
  }
  return out;
}

}  // namespace

StatusOr<StoreLocation> ParseStoreUrl(std::string_view url) {
  const std::string text(url);
  auto bad = [&](const std::string& why) {
    return Status::InvalidArgument("--store '" + text + "': " + why +
                                   " (expected s3://HOST:PORT/BUCKET/PREFIX or s3+https://HOST[:PORT]/BUCKET/PREFIX)");
  };
  StoreLocation loc;
  if (url.starts_with("s3://")) {
    loc.scheme = "http";
    url.remove_prefix(5);
  } else if (url.starts_with("s3+https://")) {
    loc.scheme = "https";
    url.remove_prefix(11);
  } else {
    return bad("unknown scheme");
  }
  const size_t slash = url.find('/');
  const std::string_view authority = url.substr(0, slash);
  std::string_view path = slash == std::string_view::npos ? std::string_view() : url.substr(slash + 1);
  const size_t colon = authority.rfind(':');
  loc.host = std::string(authority.substr(0, colon));
  if (colon == std::string_view::npos) {
    loc.port = loc.scheme == "https" ? 443 : 80;
  } else {
    const std::string_view port = authority.substr(colon + 1);
    auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), loc.port);
    if (ec != std::errc() || end != port.data() + port.size() || loc.port < 1 || loc.port > 65535)
      return bad("bad port '" + std::string(port) + "'");
  }
  if (loc.host.empty()) return bad("no host");
  const size_t bucket_end = path.find('/');
  loc.bucket = std::string(path.substr(0, bucket_end));
  if (!IsBucketName(loc.bucket))
    return bad(loc.bucket.empty() ? "no bucket"
                                  : "bucket '" + loc.bucket + "' is not a valid S3 bucket name (3-63 of a-z 0-9 . -)");
  loc.prefix = bucket_end == std::string_view::npos ? "" : FoldPrefix(path.substr(bucket_end + 1));
  return loc;
}

}  // namespace armature::server
