// Loading through tinygltf with the resources map as its file system, and
// the GLB container's own checks (tinygltf trusts its chunk lengths).
#include "gltf_importer.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "armature/base/utf8.h"

namespace armature::gltf_internal {
namespace {

std::string UrlDecode(std::string_view s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
      out += static_cast<char>(std::stoi(std::string(s.substr(i + 1, 2)), nullptr, 16));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

struct ResourceFiles {
  const ResourceMap* resources;
  std::vector<std::string> missing;

  // tinygltf asks for the url-decoded uri, possibly as "./uri".
  const std::string* Find(std::string path) const {
    if (path.rfind("./", 0) == 0) path = path.substr(2);
    if (auto it = resources->find(path); it != resources->end()) return &it->second;
    for (const auto& [uri, bytes] : *resources)
      if (UrlDecode(uri) == path) return &bytes;
    return nullptr;
  }
};

bool FileExists(const std::string& path, void* user) {
  auto* files = static_cast<ResourceFiles*>(user);
  if (files->Find(path)) return true;
  const std::string name = path.rfind("./", 0) == 0 ? path.substr(2) : path;
  if (std::find(files->missing.begin(), files->missing.end(), name) == files->missing.end())
    files->missing.push_back(name);
  return false;
}

std::string ExpandFilePath(const std::string& path, void*) { return path; }

bool ReadWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  const std::string* bytes = static_cast<ResourceFiles*>(user)->Find(path);
  if (!bytes) {
    if (err) *err += "resource '" + path + "' was not provided";
    return false;
  }
  out->assign(bytes->begin(), bytes->end());
  return true;
}

bool WriteWholeFile(std::string*, const std::string&, const std::vector<unsigned char>&, void*) { return false; }

// Images are kept as stored, never decoded. A uri's bytes (data: or a
// resource) are copied here; a bufferView's are read by the importer, which
// checks the view against its buffer (tinygltf passes them unchecked).
bool KeepImageBytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int, const unsigned char* bytes,
                    int size, void*) {
  if (image->bufferView < 0 && size > 0) image->image.assign(bytes, bytes + size);
  return true;
}

std::string Trim(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  return s;
}

uint32_t LittleEndian32(std::string_view bytes, size_t at) {
  uint32_t v = 0;
  for (size_t k = 0; k < 4; ++k) v |= static_cast<uint32_t>(static_cast<unsigned char>(bytes[at + k])) << (8 * k);
  return v;
}

// The GLB container (glTF 2.0, "Binary glTF Layout"): a 12-byte header
// (magic, version, length) and chunks of an 8-byte header (length, type) and
// that many bytes, JSON first, then an optional BIN. tinygltf 2.7.0 trusts
// the BIN chunk's length 8 bytes too far, so every length is checked here
// before it sees the bytes. Returns the `length` bytes the header declares.
StatusOr<std::string_view> CheckGlbContainer(std::string_view bytes) {
  constexpr uint32_t kJson = 0x4E4F534A, kBin = 0x004E4942;
  if (bytes.size() < 20)
    return Status::InvalidArgument("glb: " + std::to_string(bytes.size()) +
                                   " bytes are too few for a header and a JSON chunk (20 bytes at least)");
  if (bytes.substr(0, 4) != "glTF")
    return Status::InvalidArgument("glb: the file does not start with the magic 'glTF' (found '" +
                                   EscapeForMessage(bytes.substr(0, 4)) + "')");
  if (const uint32_t version = LittleEndian32(bytes, 4); version != 2)
    return Status::InvalidArgument("glb: header version " + std::to_string(version) + " is not 2");
  const uint64_t length = LittleEndian32(bytes, 8);
  if (length > bytes.size() || length < 20)
    return Status::InvalidArgument("glb: header length " + std::to_string(length) + " does not fit the file's " +
                                   std::to_string(bytes.size()) + " bytes");
  const uint64_t json_length = LittleEndian32(bytes, 12);
  if (LittleEndian32(bytes, 16) != kJson)
    return Status::InvalidArgument("glb: the first chunk (at byte 12) is not of type JSON");
  const uint64_t json_end = 20 + json_length;
  if (json_length == 0 || json_end > length)
    return Status::InvalidArgument("glb: JSON chunk length " + std::to_string(json_length) + " at byte 12 runs past " +
                                   "the header's length of " + std::to_string(length) + " bytes");
  if (json_end < length) {
    if (json_end + 8 > length)
      return Status::InvalidArgument("glb: " + std::to_string(length - json_end) +
                                     " bytes after the JSON chunk (at byte " + std::to_string(json_end) +
                                     ") are too few for a chunk header");
    const uint64_t bin_length = LittleEndian32(bytes, json_end);
    if (LittleEndian32(bytes, json_end + 4) != kBin)
      return Status::InvalidArgument("glb: the second chunk (at byte " + std::to_string(json_end) +
                                     ") is not of type BIN");
    if (json_end + 8 + bin_length > length)
      return Status::InvalidArgument("glb: BIN chunk length " + std::to_string(bin_length) + " at byte " +
                                     std::to_string(json_end) + " runs past the header's length of " +
                                     std::to_string(length) + " bytes");
  }
  return bytes.substr(0, length);
}

}  // namespace

StatusOr<tinygltf::Model> Load(std::string_view bytes, bool binary, const ResourceMap& resources) {
  if (bytes.size() > std::numeric_limits<unsigned int>::max())
    return Status::InvalidArgument("glTF: file is larger than 4 GiB");
  if (binary) {
    ARMATURE_ASSIGN_OR_RETURN(auto container, CheckGlbContainer(bytes));
    bytes = container;
  }
  ResourceFiles files{&resources, {}};
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks({&FileExists, &ExpandFilePath, &ReadWholeFile, &WriteWholeFile, &files});
  loader.SetImageLoader(&KeepImageBytes, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const auto size = static_cast<unsigned int>(bytes.size());
  const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                                       reinterpret_cast<const unsigned char*>(bytes.data()), size, "")
                         : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), size, "");
  if (ok) return model;
  for (const std::string& name : files.missing)
    if (err.find("File not found : " + name) != std::string::npos)
      return Status::InvalidArgument("buffer uri '" + EscapeForMessage(name, 200) +
                                     "' was not provided: pass the file's bytes as a resource keyed by its uri");
  return Status::InvalidArgument("glTF: " + EscapeForMessage(Trim(err.empty() ? warn : err), 400));
}

}  // namespace armature::gltf_internal
