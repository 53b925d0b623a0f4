// Reading a whole file.
#pragma once

#include <filesystem>
#include <string>

#include "armature/engine/status.h"

namespace armature::server {

// The file's bytes, or NOT_FOUND "cannot read <path>" (callers that need
// another code or more context give their own message).
StatusOr<std::string> ReadFile(const std::filesystem::path& path);

}  // namespace armature::server
