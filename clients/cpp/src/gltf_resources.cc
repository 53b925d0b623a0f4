#include "gltf_resources.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace armature::client::detail {
namespace fs = std::filesystem;
namespace {

ClientError Invalid(const std::string& message) {
  return ClientError(grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, message));
}

// A uri's %XX escapes decoded (glTF uris are URI references).
std::string PercentDecoded(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// Why `path` (decoded) may name a file outside the .gltf's folder, or "".
std::string OutsideReason(const std::string& path) {
  if (path.rfind("file:", 0) == 0) return "a file: uri";
  if (path.empty()) return "an empty uri";
  if (path.front() == '/' || path.front() == '\\') return "an absolute path";
  if (path.size() > 1 && path[1] == ':') return "an absolute path";  // C:\...
  if (path.find('\0') != std::string::npos) return "a NUL byte";
  std::istringstream parts(path);
  for (std::string part; std::getline(parts, part, '/');) {
    std::istringstream sub(part);
    for (std::string p; std::getline(sub, p, '\\');)
      if (p == "..") return "a '..' component";
  }
  return "";
}

// The file `decoded` names, for a uri the user allowed to point anywhere.
fs::path OutsidePath(const fs::path& folder, const std::string& decoded) {
  std::string p = decoded;
  if (p.rfind("file://", 0) == 0)
    p = p.substr(7);  // file:///etc/x → /etc/x (an empty host)
  else if (p.rfind("file:", 0) == 0)
    p = p.substr(5);
  return fs::path(p).is_absolute() ? fs::path(p) : folder / p;
}

std::string ReadOrThrow(const fs::path& path, const std::string& uri) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ClientError(
        grpc::Status(grpc::StatusCode::NOT_FOUND, "cannot read " + path.string() + " (buffer uri '" + uri + "')"));
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

std::vector<UploadFile> GltfResources(const fs::path& gltf_path, const std::string& gltf_text, bool allow_outside) {
  std::vector<UploadFile> resources;
  const auto j = nlohmann::json::parse(gltf_text, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("buffers") || !j["buffers"].is_array()) return resources;
  const fs::path folder = gltf_path.parent_path().empty() ? fs::path(".") : gltf_path.parent_path();
  std::error_code ec;
  const fs::path real_folder = fs::weakly_canonical(fs::absolute(folder), ec);
  for (const auto& b : j["buffers"]) {  // images are not needed for animation
    if (!b.is_object() || !b.contains("uri") || !b["uri"].is_string()) continue;
    const std::string uri = b["uri"];
    if (uri.rfind("data:", 0) == 0) continue;
    const std::string decoded = PercentDecoded(uri);
    if (decoded.rfind("file:", 0) != 0 && uri.find("://") != std::string::npos) continue;
    const std::string lexical = OutsideReason(decoded);
    fs::path path;
    if (allow_outside) {
      path = OutsidePath(folder, decoded);
    } else {
      std::string reason = lexical;
      if (reason.empty()) {
        path = folder / decoded;
        // A symlink may lead out of the folder too: compare real paths.
        const fs::path real = fs::weakly_canonical(fs::absolute(path), ec);
        const auto [end, _] = std::mismatch(real_folder.begin(), real_folder.end(), real.begin(), real.end());
        if (ec || end != real_folder.end()) reason = "a link out of the folder";
      }
      if (!reason.empty())
        throw Invalid(
            gltf_path.filename().string() + ": buffer uri '" + uri + "' (" + reason +
            ") is not in the .gltf's folder (" + folder.string() +
            ") or its subfolders, the only files uploaded; pass --allow-outside-resources to upload it anyway");
    }
    resources.push_back({uri, ReadOrThrow(path, uri)});
  }
  return resources;
}

}  // namespace armature::client::detail
