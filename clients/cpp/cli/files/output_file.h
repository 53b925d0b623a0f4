// Files the CLI writes (`export -o`, `skin -o`): the format comes from the
// file's extension unless a flag names it, and a file is only written whole.
#pragma once

#include <string>
#include <string_view>

namespace armature::cli {

// "bvh" for "out/Walk.BVH"; "" when the name has no extension.
std::string ExtensionFormat(const std::string& path);

// `path` with its extension replaced by `extension` (".bvh").
std::string WithExtension(const std::string& path, std::string_view extension);

// Writes `bytes` to `path`; on failure removes what was written and throws
// naming the file.
void WriteOutputFile(const std::string& path, std::string_view bytes);

}  // namespace armature::cli
