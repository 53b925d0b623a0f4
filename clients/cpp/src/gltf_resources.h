// Which files a .gltf's buffer uris name, and which of them the client may
// upload: a malicious .gltf must not make `armature import` send the user's
// other files (/etc/passwd, ~/.ssh/...) to a server.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "armature/client.h"

namespace armature::client::detail {

// The external buffers of the .gltf at `gltf_path` (text `gltf_text`), read
// from disk, keyed by their uri as written. data: uris are embedded and need
// nothing; uris with another "scheme://" are the server's concern. Unless
// `allow_outside`, a uri must name a file in the .gltf's folder or a
// subfolder of it: no absolute path, no "..", no file: uri, no symlink out of
// the folder; otherwise INVALID_ARGUMENT naming the uri and the CLI flag
// --allow-outside-resources.
std::vector<UploadFile> GltfResources(const std::filesystem::path& gltf_path, const std::string& gltf_text,
                                      bool allow_outside);

}  // namespace armature::client::detail
