// Reading and writing whole files, and the errors a data dir reports.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "armature/base/status.h"

namespace armature::server {

// The file's bytes, or NOT_FOUND "cannot read <path>" (callers that need
// another code or more context give their own message).
StatusOr<std::string> ReadFile(const std::filesystem::path& path);

// What a failed write in data dir `dir` reports: RESOURCE_EXHAUSTED "data
// dir <dir>: no space left on device" when the disk or quota is full
// (ENOSPC, EDQUOT), else INTERNAL "data dir <dir>: cannot <action>: <error>".
// Temporary file names are never part of it: they mean nothing to a caller.
Status DataDirError(const std::filesystem::path& dir, int err, std::string_view action);

// Writes `bytes` to dir/relative atomically: a temporary file beside it,
// fsync, rename, fsync of the directory. On failure the temporary file is
// removed and the target is unchanged; the error is a DataDirError.
Status WriteFileAtomic(const std::filesystem::path& dir, const std::string& relative, std::string_view bytes);

// A random hex string, for names that must not collide.
std::string RandomSuffix();

// Makes `path` a file of at least `bytes` allocated bytes (posix_fallocate,
// else written zeros). False when the disk has no room for it.
bool AllocateFile(const std::filesystem::path& path, int64_t bytes);

}  // namespace armature::server
